// The lag at which a channel's records line up with the model's
// simulation: the start of a delay's refit (sensor_delay, MODEL.md §6) when
// the delay is longer than the first-order step can reach. The score test
// and a refit from 0 see a delay through its first-order signature, a lag
// times the channel's slope, which holds for a fraction of a sample; a
// delay of several samples (a recorder 3 ms late on a 1 kHz record) or of
// hundreds of milliseconds on a slow record is out of its reach, and a
// local refit from 0 stops where the gear's ringing or the input's next
// edge first lines up (issue 56: 3 ms fitted as a half-sample shift, a
// shorter delay and a resonant filter). Aligning the records first starts
// the refit next to the true lag.
#ifndef ESTIMATION_ALIGNMENT_LAG_H_
#define ESTIMATION_ALIGNMENT_LAG_H_

#include <string>

#include "estimation/fit_result.h"

namespace axis {

// The lag τ (s; > 0: the records are late, as a delay τ_d of MODEL.md §6)
// that minimises Σ (y_k − ŷ(t_k − τ))² over the fitted samples of
// `channel` (a MODEL.md §6 name) of every experiment of `fit` that fits
// it, ŷ the simulated channel at the fit's estimate: over whole samples in
// [−max_lag, max_lag] (each experiment's overlap, normalised by its
// length), then refined to a fraction of a sample by the parabola through
// the best whole lag and its neighbours. The experiments must share one
// output period (the first one's is used). NaN if no experiment fits the
// channel, or its records are shorter than 8 samples. Never throws.
double AlignmentLag(const FitResult& fit, const std::string& channel, double max_lag);

}  // namespace axis

#endif  // ESTIMATION_ALIGNMENT_LAG_H_
