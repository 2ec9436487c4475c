// Random numbers whose sequence this project defines: the same seed gives the
// same noise, random starts and bootstrap resamples under every compiler and
// standard library. The engine is the 64-bit Mersenne Twister (its output is
// fixed by the C++ standard, [rand.predef]: the 10000th draw from the default
// seed is 9981545732273789042); the distributions are Boost.Random's
// (boost/random/*.hpp, header-only, Debian libboost-dev), whose algorithms
// are Boost's code and so the same everywhere, where the std:: distributions'
// algorithms are left to each standard library (issue 17). The normal
// deviates use Boost's ziggurat; its only libm calls (exp, log, in the tail)
// are accurate to an ulp, so a draw may differ in its last bit between
// libms, never in its sequence.
#ifndef SIM_RANDOM_H_
#define SIM_RANDOM_H_

#include <cstddef>
#include <cstdint>

#include <boost/random/mersenne_twister.hpp>
#include <boost/random/normal_distribution.hpp>
#include <boost/random/uniform_int_distribution.hpp>
#include <boost/random/uniform_real_distribution.hpp>

namespace axis {

// The project's engine (identical in output to std::mt19937_64).
using RandomEngine = boost::random::mt19937_64;

// A standard normal deviate (mean 0, standard deviation 1).
inline double StandardNormal(RandomEngine& rng) {
  return boost::random::normal_distribution<double>(0.0, 1.0)(rng);
}

// Uniform on [low, high); requires low ≤ high (Boost asserts in debug builds).
inline double UniformReal(double low, double high, RandomEngine& rng) {
  return boost::random::uniform_real_distribution<double>(low, high)(rng);
}

// Uniform on the integers low, …, high (both included); requires low ≤ high.
inline std::size_t UniformIndex(std::size_t low, std::size_t high, RandomEngine& rng) {
  return boost::random::uniform_int_distribution<std::size_t>(low, high)(rng);
}

}  // namespace axis

#endif  // SIM_RANDOM_H_
