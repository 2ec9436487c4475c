// Welch-averaged spectra of a sampled input–output record and the H1
// estimate of the frequency response from them (Bendat & Piersol, "Random
// Data", 4th ed., 2010, §9.2 and §11.2): the record is cut into segments
// of L samples overlapping by half, each segment's mean is removed and a
// Hann window applied, the segments' discrete Fourier transforms (FFTW3's
// real-to-complex transform, Debian libfftw3-dev) give the one-sided
// auto- and cross-spectral densities averaged over the segments, and
//   H1(f) = G_uy(f)/G_uu(f),   γ²(f) = |G_uy(f)|²/(G_uu(f)·G_yy(f)).
// H1 is unbiased by noise on the output; γ² is 1 where the output is a
// linear, noise-free function of the input. The normalised random error of
// |H1| is sqrt(1 − γ²)/(|γ|·sqrt(2·n_d)) with n_d the number of averages
// (Bendat & Piersol, Table 9.6). docs/frequency-response.md.
#ifndef COMMON_SPECTRAL_H_
#define COMMON_SPECTRAL_H_

#include <complex>
#include <cstddef>
#include <string>
#include <vector>

namespace axis {

// How a record is cut into segments.
struct WelchOptions {
  // Samples per segment, a power of two ≥ 16; 0: WelchSegmentLength.
  int segment_length = 0;
  // The fewest segments the automatic length allows (≥ 1).
  int min_averages = 8;
};

// The largest power of two L ≥ 16 such that a record of `samples` samples
// holds at least `min_averages` segments of L samples at 50 % overlap
// (WelchSegmentCount), or 0 if even L = 16 does not. Never throws.
int WelchSegmentLength(size_t samples, int min_averages);

// The number of segments of `segment_length` samples, overlapping by half
// (hop L/2), that fit in `samples`: ⌊(N − L)/(L/2)⌋ + 1, 0 if N < L.
// Never throws.
int WelchSegmentCount(size_t samples, int segment_length);

// The averaged one-sided spectra of input u and output y on the bins
// f_k = k/(L·Δt), k = 0 … L/2 (Hz). Densities in unit²/Hz (the input's,
// the output's and their product's unit): G = 2·Σ_s conj(U_s)·Y_s /
// (K·f_s·Σw²), with the factor 2 left out at k = 0 and k = L/2.
struct WelchSpectra {
  double sample_period = 0.0;  // Δt, s
  int segment_length = 0;      // L, samples
  int averages = 0;            // K, segments averaged
  std::vector<double> frequency;             // Hz, L/2 + 1 bins
  std::vector<double> uu, yy;                // G_uu, G_yy
  std::vector<std::complex<double>> uy;      // G_uy
  // Per segment, the input's power above DC (Σ_{k≥1} |U_k|², window and
  // mean removal applied; relative use only).
  std::vector<double> segment_input_power;
};

// The spectra of `u` and `y` (the same length N, sampled every
// `sample_period` s). Throws std::invalid_argument ("expected …, got …")
// if the lengths differ, the period is not positive and finite, a value is
// not finite, segment_length is not 0 or a power of two ≥ 16, or the record
// holds fewer than one segment (an explicit length) or than
// min_averages segments of 16 samples (automatic). Thread-safe: the FFTW
// plan of each length is made once, under a lock, and executed on the
// caller's arrays (fftw_execute_dft_r2c).
WelchSpectra ComputeWelchSpectra(const std::vector<double>& u, const std::vector<double>& y,
                                 double sample_period, const WelchOptions& options = {});

// The H1 estimate and the coherence on the bins of a WelchSpectra.
struct FrequencyResponseEstimate {
  std::vector<double> frequency;          // Hz
  std::vector<std::complex<double>> h1;   // output unit per input unit
  std::vector<double> coherence;          // γ², in [0, 1]
  int averages = 0;
  int segment_length = 0;
};

// H1 = G_uy/G_uu and γ² = |G_uy|²/(G_uu·G_yy) per bin; 0 (both) where
// G_uu or G_yy is 0. Never throws (but std::bad_alloc).
FrequencyResponseEstimate EstimateH1(const WelchSpectra& s);

// The normalised random error of |H1| at coherence γ² with n_d averages,
// sqrt(1 − γ²)/(|γ|·sqrt(2·n_d)) (Bendat & Piersol, Table 9.6); +inf for
// γ² = 0. Never throws.
double H1RandomError(double coherence, int averages);

// Whether an input excites a band rather than lines or a transient, from
// its Welch spectra: the excited bins are those whose G_uu is within
// `within_db` of the largest G_uu above DC; the input excites a band if
//   - some run of consecutive excited bins above DC is at least `min_bins`
//     bins long and spans an octave (its top bin at least twice its
//     lowest), and
//   - the input is present in at least half of the segments (a segment's
//     power above DC at least `segment_fraction` of the largest
//     segment's): a sustained excitation, not one transient.
// A chirp or sweep over more than min_bins bins, a PRBS whose bits are
// shorter than a few bins' periods, white noise and a multisine whose
// lines are denser than the bins excite one; a single sine (its Hann main
// lobe is at most 4 bins), a ramp (2–3 bins), a square wave with two or
// more periods per segment (lines at its odd harmonics with empty bins
// between) and a single step (present in one or two segments) do not.
struct BandCriterion {
  double within_db = 20.0;          // dB below the peak of G_uu, > 0
  int min_bins = 6;                 // ≥ 2
  double segment_fraction = 0.01;   // in [0, 1]
};

struct BandExcitation {
  bool band = false;
  double f_low = 0.0, f_high = 0.0;  // Hz: the longest run of excited bins
  int bins = 0;                      // its length in bins
  int segments_excited = 0;          // segments where the input is present
  std::string reason;                // why not, in words ("" if band)
};

// Applies the criterion to the input's spectra `s` (ComputeWelchSpectra
// with the input as u). Throws std::invalid_argument if `s` has fewer
// than 2 bins or no segment, or the criterion is out of range.
BandExcitation FindExcitedBand(const WelchSpectra& s, const BandCriterion& criterion = {});

}  // namespace axis

#endif  // COMMON_SPECTRAL_H_
