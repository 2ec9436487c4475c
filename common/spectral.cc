#include "common/spectral.h"

#include <fftw3.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <sstream>
#include <stdexcept>

namespace axis {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kMinSegment = 16;

bool IsPowerOfTwo(int n) { return n > 0 && (n & (n - 1)) == 0; }

// FFTW's planner is not thread-safe; executing a plan on new arrays is
// (fftw_execute_dft_r2c). One plan per length, made on first use under the
// lock; the cache destroys its plans when the process ends (a plan left
// behind by a destroyed map is a leak to LeakSanitizer).
class PlanCache {
 public:
  ~PlanCache() {
    for (auto& [n, plan] : plans_) fftw_destroy_plan(plan);
    fftw_cleanup();
  }

  fftw_plan For(int n) {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = plans_.find(n);
    if (it != plans_.end()) return it->second;
    double* in = fftw_alloc_real(n);
    fftw_complex* out = fftw_alloc_complex(n / 2 + 1);
    const fftw_plan plan = fftw_plan_dft_r2c_1d(n, in, out, FFTW_ESTIMATE);
    fftw_free(in);
    fftw_free(out);
    if (plan == nullptr) throw std::runtime_error("FFTW could not plan a transform");
    plans_.emplace(n, plan);
    return plan;
  }

 private:
  std::mutex mutex_;
  std::map<int, fftw_plan> plans_;
};

fftw_plan PlanFor(int n) {
  static PlanCache cache;
  return cache.For(n);
}

struct FftwFree {
  void operator()(void* p) const { fftw_free(p); }
};

// The windowed, mean-removed segment of `x` starting at `from` into `in`.
void FillSegment(const std::vector<double>& x, size_t from, const std::vector<double>& window,
                 double* in) {
  const size_t n = window.size();
  double mean = 0.0;
  for (size_t j = 0; j < n; ++j) mean += x[from + j];
  mean /= static_cast<double>(n);
  for (size_t j = 0; j < n; ++j) in[j] = (x[from + j] - mean) * window[j];
}

void CheckRecord(const std::vector<double>& u, const std::vector<double>& y,
                 double sample_period, const WelchOptions& options) {
  std::ostringstream m;
  if (u.size() != y.size()) {
    m << "ComputeWelchSpectra: expected input and output of the same length, got " << u.size()
      << " and " << y.size();
  } else if (!(sample_period > 0.0) || !std::isfinite(sample_period)) {
    m << "ComputeWelchSpectra: expected a positive sample period, got " << sample_period;
  } else if (options.segment_length != 0 &&
             (!IsPowerOfTwo(options.segment_length) || options.segment_length < kMinSegment)) {
    m << "ComputeWelchSpectra: expected a segment length of 0 or a power of two >= "
      << kMinSegment << ", got " << options.segment_length;
  } else if (options.min_averages < 1) {
    m << "ComputeWelchSpectra: expected min_averages >= 1, got " << options.min_averages;
  } else {
    for (size_t k = 0; k < u.size(); ++k) {
      if (!std::isfinite(u[k]) || !std::isfinite(y[k])) {
        m << "ComputeWelchSpectra: expected finite samples, got a non-finite one at sample "
          << k;
        break;
      }
    }
  }
  if (!m.str().empty()) throw std::invalid_argument(m.str());
}

}  // namespace

int WelchSegmentCount(size_t samples, int segment_length) {
  if (segment_length < 2 || samples < static_cast<size_t>(segment_length)) return 0;
  const size_t hop = static_cast<size_t>(segment_length / 2);
  return static_cast<int>((samples - segment_length) / hop + 1);
}

int WelchSegmentLength(size_t samples, int min_averages) {
  int best = 0;
  for (long n = kMinSegment; n <= (1L << 30) && static_cast<size_t>(n) <= samples; n *= 2) {
    if (WelchSegmentCount(samples, static_cast<int>(n)) >= min_averages) {
      best = static_cast<int>(n);
    }
  }
  return best;
}

WelchSpectra ComputeWelchSpectra(const std::vector<double>& u, const std::vector<double>& y,
                                 double sample_period, const WelchOptions& options) {
  CheckRecord(u, y, sample_period, options);
  int n = options.segment_length;
  if (n == 0) n = WelchSegmentLength(u.size(), options.min_averages);
  const int segments = WelchSegmentCount(u.size(), n);
  if (n == 0 || segments < 1) {
    std::ostringstream m;
    m << "ComputeWelchSpectra: expected a record of at least "
      << (options.segment_length != 0
              ? options.segment_length
              : kMinSegment / 2 * (options.min_averages + 1))
      << " samples, got " << u.size();
    throw std::invalid_argument(m.str());
  }
  std::vector<double> window(n);
  double window_power = 0.0;
  for (int j = 0; j < n; ++j) {
    window[j] = 0.5 - 0.5 * std::cos(2.0 * kPi * j / n);  // periodic Hann
    window_power += window[j] * window[j];
  }
  const int bins = n / 2 + 1;
  WelchSpectra s;
  s.sample_period = sample_period;
  s.segment_length = n;
  s.averages = segments;
  s.frequency.resize(bins);
  s.uu.assign(bins, 0.0);
  s.yy.assign(bins, 0.0);
  s.uy.assign(bins, {0.0, 0.0});
  s.segment_input_power.assign(segments, 0.0);
  const fftw_plan plan = PlanFor(n);
  std::unique_ptr<double, FftwFree> in(fftw_alloc_real(n));
  std::unique_ptr<fftw_complex, FftwFree> fu(fftw_alloc_complex(bins));
  std::unique_ptr<fftw_complex, FftwFree> fy(fftw_alloc_complex(bins));
  for (int seg = 0; seg < segments; ++seg) {
    const size_t from = static_cast<size_t>(seg) * (n / 2);
    FillSegment(u, from, window, in.get());
    fftw_execute_dft_r2c(plan, in.get(), fu.get());
    FillSegment(y, from, window, in.get());
    fftw_execute_dft_r2c(plan, in.get(), fy.get());
    for (int k = 0; k < bins; ++k) {
      const std::complex<double> a(fu.get()[k][0], fu.get()[k][1]);
      const std::complex<double> b(fy.get()[k][0], fy.get()[k][1]);
      s.uu[k] += std::norm(a);
      s.yy[k] += std::norm(b);
      s.uy[k] += std::conj(a) * b;
      if (k > 0) s.segment_input_power[seg] += std::norm(a);
    }
  }
  const double fs = 1.0 / sample_period;
  for (int k = 0; k < bins; ++k) {
    const double scale = (k == 0 || k == n / 2 ? 1.0 : 2.0) / (segments * fs * window_power);
    s.frequency[k] = k * fs / n;
    s.uu[k] *= scale;
    s.yy[k] *= scale;
    s.uy[k] *= scale;
  }
  return s;
}

FrequencyResponseEstimate EstimateH1(const WelchSpectra& s) {
  FrequencyResponseEstimate e;
  e.frequency = s.frequency;
  e.averages = s.averages;
  e.segment_length = s.segment_length;
  e.h1.assign(s.frequency.size(), {0.0, 0.0});
  e.coherence.assign(s.frequency.size(), 0.0);
  for (size_t k = 0; k < s.frequency.size(); ++k) {
    if (!(s.uu[k] > 0.0) || !(s.yy[k] > 0.0)) continue;
    e.h1[k] = s.uy[k] / s.uu[k];
    e.coherence[k] = std::min(1.0, std::norm(s.uy[k]) / (s.uu[k] * s.yy[k]));
  }
  return e;
}

double H1RandomError(double coherence, int averages) {
  if (!(coherence > 0.0) || averages < 1) return std::numeric_limits<double>::infinity();
  const double g2 = std::min(coherence, 1.0);
  return std::sqrt(1.0 - g2) / (std::sqrt(g2) * std::sqrt(2.0 * averages));
}

BandExcitation FindExcitedBand(const WelchSpectra& s, const BandCriterion& criterion) {
  const std::vector<double>& uu = s.uu;
  if (s.frequency.size() != uu.size() || uu.size() < 2 || s.segment_input_power.empty()) {
    throw std::invalid_argument("FindExcitedBand: expected spectra of at least 2 bins and one "
                                "segment, got " +
                                std::to_string(uu.size()) + " bins and " +
                                std::to_string(s.segment_input_power.size()) + " segments");
  }
  if (!(criterion.within_db > 0.0) || criterion.min_bins < 2 ||
      !(criterion.segment_fraction >= 0.0 && criterion.segment_fraction <= 1.0)) {
    throw std::invalid_argument(
        "FindExcitedBand: expected within_db > 0, min_bins >= 2 and segment_fraction in [0, 1], "
        "got " + std::to_string(criterion.within_db) + ", " +
        std::to_string(criterion.min_bins) + " and " +
        std::to_string(criterion.segment_fraction));
  }
  BandExcitation out;
  const double peak = *std::max_element(uu.begin() + 1, uu.end());
  if (!(peak > 0.0)) {
    out.reason = "no band: no input power above DC";
    return out;
  }
  const double level = peak * std::pow(10.0, -criterion.within_db / 10.0);
  size_t best_from = 1, best_length = 0;
  for (size_t k = 1; k < uu.size();) {
    size_t end = k;
    while (end < uu.size() && uu[end] >= level) ++end;
    if (end - k > best_length) {
      best_from = k;
      best_length = end - k;
    }
    k = end + 1;
  }
  out.bins = static_cast<int>(best_length);
  out.f_low = s.frequency[best_from];
  out.f_high = s.frequency[best_from + std::max<size_t>(best_length, 1) - 1];
  const double most =
      *std::max_element(s.segment_input_power.begin(), s.segment_input_power.end());
  for (double p : s.segment_input_power) {
    out.segments_excited += p >= criterion.segment_fraction * most ? 1 : 0;
  }
  const bool octave = best_from + best_length - 1 >= 2 * best_from;
  const bool sustained = 2 * out.segments_excited >= static_cast<int>(s.segment_input_power.size());
  out.band = out.bins >= criterion.min_bins && octave && sustained;
  std::ostringstream m;
  if (out.bins < criterion.min_bins || !octave) {
    m << "no band: the longest run of bins within " << criterion.within_db
      << " dB of the input's peak is " << out.bins << " bin" << (out.bins == 1 ? "" : "s")
      << " (" << out.f_low << " to " << out.f_high << " Hz; a band needs " << criterion.min_bins
      << " bins and an octave)";
  } else if (!sustained) {
    m << "no band: the input is present in " << out.segments_excited << " of "
      << s.segment_input_power.size() << " segments (a transient, not a sustained excitation)";
  }
  out.reason = m.str();
  return out;
}

}  // namespace axis
