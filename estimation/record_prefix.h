// The first part of a record, for the horizon continuation of a fit
// (estimation/internal/fitter.h: stages of growing horizon) and for a fit
// that leaves a record's tail unfitted (discovery/internal/discovery_loop.h
// TrimAheadOfTheRecords: a channel read ahead of its time).
#ifndef ESTIMATION_RECORD_PREFIX_H_
#define ESTIMATION_RECORD_PREFIX_H_

#include "estimation/estimation_problem.h"

namespace axis {

// The first `horizon` seconds of an experiment (all of it if shorter): its
// samples up to the horizon, simulated `lookahead` seconds further (whole
// output periods, within the record) so that a channel read ahead of its
// time (a sensor delay below zero, MODEL.md §6) sees the same trajectory as
// on the whole record, not the signal held after the stage's end: a stage's
// cost is then the prefix of the whole record's, which the refits' BIC
// bounds rely on (estimation/fit.h). lookahead ≥ 0.
FitExperiment Truncate(const FitExperiment& e, double horizon, double lookahead = 0.0);

// How far ahead of its time the problem may read a channel: the most
// negative of each delayed channel's τ_d and, where it is free, its lower
// bound, as a positive time (s); 0 without advances.
double Lookahead(const EstimationProblem& problem);

}  // namespace axis

#endif  // ESTIMATION_RECORD_PREFIX_H_
