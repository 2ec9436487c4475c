// A level one fit publishes for others running beside it (the force map's
// forms, discovery/force_map.cc): competing refits of which only the
// lowest BIC matters stop once they can no longer end below it
// (estimation/fit_control.h FitControl::publish_level, pending_level).
#ifndef ESTIMATION_SHARED_LEVEL_H_
#define ESTIMATION_SHARED_LEVEL_H_

#include <condition_variable>
#include <mutex>
#include <optional>

namespace axis {

// A level that one fit (the leader) decides while others run beside it
// (FitControl::publish_level, pending_level): the leader's FitParameters
// publishes its BIC when it ends (+inf if it stopped early, failed or
// threw). A fit given it as pending_level records the BIC bounds of its
// shorter horizons until then, and once it is published stops at the first
// stage whose bound passed `factor` times it: it ends as it would have
// ended had it run after the leader with control.abandon_above_bic set to
// that level, only without waiting for the leader to start. The leader
// must run before or beside its pending fits (FitConcurrently: a lower
// index), or they wait for ever. Thread-safe.
class SharedLevel {
 public:
  // factor: the margin (kStopFactor), > 0; throws std::invalid_argument
  // otherwise.
  explicit SharedLevel(double factor);
  SharedLevel(const SharedLevel&) = delete;
  SharedLevel& operator=(const SharedLevel&) = delete;
  // Publishes the leader's BIC (+inf: no level); later calls are ignored.
  void Publish(double bic);
  // factor·BIC once published (+inf for no level), else nothing.
  std::optional<double> TryAbandonAbove() const;
  // factor·BIC, waiting until it is published.
  double AbandonAbove() const;

 private:
  // factor·BIC or +inf; mutex_ held.
  double Threshold() const;

  const double factor_;
  mutable std::mutex mutex_;
  mutable std::condition_variable published_;
  bool known_ = false;
  double bic_ = 0.0;
};

}  // namespace axis

#endif  // ESTIMATION_SHARED_LEVEL_H_
