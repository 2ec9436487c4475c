// Uncertainty of a fit's estimate beyond the Gauss–Newton covariance
// (issue 9): the curvature of the cost measured at the scale of the
// confidence interval, and the residual bootstrap that cross-checks it.
//
// Why: the cost of the model as specified (MODEL.md §3) is piecewise smooth.
// Near a grazing backlash contact (the gear only just reaches the edge of
// the backlash) the event time is hypersensitive to the parameters — the
// saltation term divides by the guard's rate, which goes to zero — so JᵀJ at
// the estimate describes the cost only within a tiny neighbourhood and can
// overstate the information by orders of magnitude. Measured on the PRBS
// campaign (scripts/optimum-campaign): T_p estimates 3–8 Gauss–Newton
// standard errors from the truth while their cost lay within 1 of the
// truth's.
//
// The methods, each in the file its name says:
// - estimation/cost_at.h: CostAt, the cost at a point, which they evaluate;
// - estimation/likelihood_ratio.h: RatioInterval, the interval of one
//   parameter, and LikelihoodRatioIntervals, the cost scanned along the
//   Gauss–Newton profile directions;
// - estimation/profile_likelihood.h: ProfileLikelihoodIntervals, the cost
//   minimised over the other parameters (the profile likelihood);
// - estimation/residual_bootstrap.h: ResidualBootstrap, refits of
//   resampled residuals that cross-check the intervals.
// Which one a fit runs: estimation/solver_settings.h, estimation/fit.h.
#ifndef ESTIMATION_UNCERTAINTY_H_
#define ESTIMATION_UNCERTAINTY_H_

#include "estimation/cost_at.h"
#include "estimation/likelihood_ratio.h"
#include "estimation/profile_likelihood.h"
#include "estimation/residual_bootstrap.h"

#endif  // ESTIMATION_UNCERTAINTY_H_
