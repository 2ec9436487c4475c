// Input shapers (sim/input_shaper.h, Reference::shaper in sim/controller.h;
// MODEL.md §5 "Input shaping") against their closed forms: each shaper's
// amplitudes and duration; ZV, MZV and ZVD leave no vibration at their
// design point, the EI family the tolerance V over its published band; a
// shaped step on a second-order system (its response a sum of closed-form
// step responses) is still after the last impulse; a shaped trapezoid
// ends where the unshaped one does, later by the shaper's duration, and
// leaves a lightly damped mode still; the `shaper:` and `tune.move`
// shaper keys.
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "io/yaml_util.h"
#include "run/load_fit_job.h"
#include "sim/controller.h"
#include "sim/drive_config.h"
#include "sim/input_shaper.h"
#include "tune/klipper_shaper_rule.h"
#include "tune/move_response.h"
#include "tune/tune_settings.h"

namespace axis {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kV = kShaperVibrationTolerance;

const ShaperType kAll[] = {ShaperType::kZV, ShaperType::kMZV, ShaperType::kZVD,
                           ShaperType::kEI, ShaperType::k2HumpEI, ShaperType::k3HumpEI};

// The shaper's duration in damped periods (Klipper's table at ζ = 0: 0.5,
// 0.75, 1, 1, 1.5, 2 over shaper_freq).
double PeriodsOf(ShaperType t) {
  switch (t) {
    case ShaperType::kZV: return 0.5;
    case ShaperType::kMZV: return 0.75;
    case ShaperType::kZVD: case ShaperType::kEI: return 1.0;
    case ShaperType::k2HumpEI: return 1.5;
    case ShaperType::k3HumpEI: return 2.0;
    case ShaperType::kNone: return 0.0;
  }
  return 0.0;
}

TEST(InputShaperTest, AmplitudesArePositiveSumToOneAndSpanTheirPeriods) {
  for (ShaperType type : kAll) {
    for (double zeta : {0.0, 0.1, 0.3}) {
      const double f = 25.0;
      const InputShaper s = MakeInputShaper(type, f, zeta);
      SCOPED_TRACE(ShaperName(type) + " zeta " + std::to_string(zeta));
      ASSERT_EQ(s.amplitudes.size(), s.times.size());
      double sum = 0.0;
      for (size_t i = 0; i < s.amplitudes.size(); ++i) {
        EXPECT_GT(s.amplitudes[i], 0.0);
        sum += s.amplitudes[i];
        if (i > 0) {
          EXPECT_GT(s.times[i], s.times[i - 1]);
        }
      }
      EXPECT_NEAR(sum, 1.0, 1e-15);
      EXPECT_EQ(s.times.front(), 0.0);
      EXPECT_NEAR(s.Duration(), PeriodsOf(type) / (f * std::sqrt(1.0 - zeta * zeta)), 1e-15);
    }
  }
  // ZV: A = [1, K]/(1 + K), K = exp(−ζπ/√(1−ζ²)) (Singer & Seering 1990).
  const double K = std::exp(-0.1 * kPi / std::sqrt(0.99));
  const InputShaper zv = MakeInputShaper(ShaperType::kZV, 10.0, 0.1);
  EXPECT_NEAR(zv.amplitudes[0], 1.0 / (1.0 + K), 1e-15);
  EXPECT_NEAR(zv.amplitudes[1], K / (1.0 + K), 1e-15);
  const InputShaper none = MakeInputShaper(ShaperType::kNone, 0.0, 0.0);
  EXPECT_EQ(none.amplitudes, std::vector<double>{1.0});
  EXPECT_EQ(none.Duration(), 0.0);
  EXPECT_EQ(ShaperVibration(none, 12.0, 0.1), 1.0);
}

// The zero-vibration shapers cancel their design mode exactly, at any
// damping; the EI family leaves exactly V at (undamped) design and at most
// V over its band: EI ±20 %, 2HUMP_EI ±36 % (Klipper: ±35 %), 3HUMP_EI
// −48…+48 % (Klipper: −45…+50 %), the band edges from the closed forms.
TEST(InputShaperTest, ResidualVibrationAtAndAroundTheDesignPoint) {
  for (ShaperType type : {ShaperType::kZV, ShaperType::kMZV, ShaperType::kZVD}) {
    for (double zeta : {0.0, 0.05, 0.1, 0.2}) {
      const InputShaper s = MakeInputShaper(type, 40.0, zeta);
      EXPECT_NEAR(ShaperVibration(s, 40.0, zeta), 0.0, 1e-14) << ShaperName(type) << " " << zeta;
    }
  }
  const InputShaper ei = MakeInputShaper(ShaperType::kEI, 40.0, 0.0);
  const InputShaper two = MakeInputShaper(ShaperType::k2HumpEI, 40.0, 0.0);
  const InputShaper three = MakeInputShaper(ShaperType::k3HumpEI, 40.0, 0.0);
  EXPECT_NEAR(ShaperVibration(ei, 40.0, 0.0), kV, 1e-14);
  EXPECT_NEAR(ShaperVibration(two, 40.0, 0.0), 0.0, 1e-14);
  EXPECT_NEAR(ShaperVibration(three, 40.0, 0.0), kV, 1e-14);
  for (int k = 0; k <= 200; ++k) {
    const double r = -1.0 + 0.01 * k;  // −1 … +1 of each band
    EXPECT_LE(ShaperVibration(ei, 40.0 * (1.0 + 0.19 * r), 0.0), kV + 1e-12);
    EXPECT_LE(ShaperVibration(two, 40.0 * (1.0 + 0.36 * r), 0.0), kV + 1e-12);
    EXPECT_LE(ShaperVibration(three, 40.0 * (1.0 + 0.48 * r), 0.0), kV + 1e-12);
  }
  EXPECT_GT(ShaperVibration(ei, 40.0 * 1.3, 0.0), kV);
  EXPECT_GT(ShaperVibration(two, 40.0 * 1.45, 0.0), kV);
  // Undamped, off design by r = f/f_design: ZV leaves |cos(πr/2)|, ZVD
  // cos²(πr/2) (Singer & Seering 1990): ZVD is the less sensitive.
  const InputShaper zv = MakeInputShaper(ShaperType::kZV, 40.0, 0.0);
  const InputShaper zvd = MakeInputShaper(ShaperType::kZVD, 40.0, 0.0);
  for (double r : {0.7, 0.9, 1.1, 1.3}) {
    EXPECT_NEAR(ShaperVibration(zv, 40.0 * r, 0.0), std::abs(std::cos(kPi * r / 2)), 1e-14);
    EXPECT_NEAR(ShaperVibration(zvd, 40.0 * r, 0.0), std::pow(std::cos(kPi * r / 2), 2), 1e-14);
  }
}

// A unit step shaped by s into x'' + 2ζωx' + ω²x = ω²u: the response is
// Σ A_i·h(t − t_i) with the closed-form step response
// h(t) = 1 − e^(−ζωt)(cos ω_d t + ζ/√(1−ζ²)·sin ω_d t).
double ShapedStep(const InputShaper& s, double f, double zeta, double t) {
  const double w = 2 * kPi * f, wd = w * std::sqrt(1 - zeta * zeta);
  double y = 0.0;
  for (size_t i = 0; i < s.amplitudes.size(); ++i) {
    const double tau = t - s.times[i];
    if (tau < 0) continue;
    y += s.amplitudes[i] *
         (1 - std::exp(-zeta * w * tau) *
                  (std::cos(wd * tau) + zeta / std::sqrt(1 - zeta * zeta) * std::sin(wd * tau)));
  }
  return y;
}

TEST(InputShaperTest, AZvShaperLeavesASecondOrderSystemStillAfterItsLastImpulse) {
  const double f = 8.0;
  for (double zeta : {0.0, 0.05, 0.15}) {
    for (ShaperType type : {ShaperType::kZV, ShaperType::kMZV, ShaperType::kZVD}) {
      const InputShaper s = MakeInputShaper(type, f, zeta);
      double unshaped = 0.0, shaped = 0.0;
      for (int k = 0; k <= 1000; ++k) {
        const double t = s.Duration() + 3.0 / f * k / 1000.0;  // three periods on
        shaped = std::max(shaped, std::abs(ShapedStep(s, f, zeta, t) - 1.0));
        unshaped = std::max(
            unshaped, std::abs(ShapedStep(MakeInputShaper(ShaperType::kNone, 0, 0), f, zeta, t) -
                               1.0));
      }
      EXPECT_LT(shaped, 1e-13) << ShaperName(type) << " zeta " << zeta;
      EXPECT_GT(unshaped, 0.1);  // the unshaped step still rings
    }
  }
}

// A trapezoid shaped by ZV is Σ A_i·P(t − t_i); it ends at the target a
// shaper's duration later; a lightly damped mode it drives
// (x'' = ω²(P(t) − x) − 2ζωx', RK4 at 0.1 ms: error ~ (ωh)⁴ ≈ 1e-8 of the
// swing) rings after the unshaped move and is still after the shaped one.
TEST(InputShaperTest, AShapedTrapezoidEndsLaterAtItsTargetAndLeavesTheModeStill) {
  Reference r;
  r.distance = 0.1;
  r.velocity = 0.5;
  r.acceleration = 10.0;
  const double f = 12.0, zeta = 0.03;
  Reference shaped = r;
  shaped.shaper = MakeInputShaper(ShaperType::kZV, f, zeta);
  EXPECT_NEAR(shaped.MoveDuration(), r.MoveDuration() + shaped.shaper.Duration(), 1e-15);
  EXPECT_NEAR(shaped.Profile(shaped.MoveDuration()), 0.1, 1e-15);
  const double t = 0.1;
  EXPECT_NEAR(shaped.Profile(t),
              shaped.shaper.amplitudes[0] * r.Profile(t) +
                  shaped.shaper.amplitudes[1] * r.Profile(t - shaped.shaper.times[1]),
              1e-15);
  const auto residual = [&](const Reference& ref) {
    const double w = 2 * kPi * f, h = 1e-4;
    double x = 0.0, v = 0.0, worst = 0.0;
    const auto acc = [&](double tt, double xx, double vv) {
      return w * w * (ref.Profile(tt) - xx) - 2 * zeta * w * vv;
    };
    for (int k = 0; k * h < ref.MoveDuration() + 1.0; ++k) {
      const double tt = k * h;
      const double k1x = v, k1v = acc(tt, x, v);
      const double k2x = v + 0.5 * h * k1v, k2v = acc(tt + 0.5 * h, x + 0.5 * h * k1x, k2x);
      const double k3x = v + 0.5 * h * k2v, k3v = acc(tt + 0.5 * h, x + 0.5 * h * k2x, k3x);
      const double k4x = v + h * k3v, k4v = acc(tt + h, x + h * k3x, k4x);
      x += h / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
      v += h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
      if (tt + h >= ref.MoveDuration()) worst = std::max(worst, std::abs(x - 0.1));
    }
    return worst;
  };
  const double unshaped_ringing = residual(r);
  const double shaped_ringing = residual(shaped);
  EXPECT_GT(unshaped_ringing, 1e-3);
  EXPECT_LT(shaped_ringing, 1e-6 * unshaped_ringing + 1e-9);
  // The smoothing against the command delayed by the centroid t̄ = A_1·t_1:
  // 0 in the cruise, ½·a·Σ A_i(t_i − t̄)² = ½·a·A_0·A_1·t_1² through the
  // 0.05 s acceleration (longer than the 0.042 s shaper), to the 1e-5 s
  // grid (a·h·t_1 ≈ 4e-6 of it).
  const double a0 = shaped.shaper.amplitudes[0], a1 = shaped.shaper.amplitudes[1];
  const double t1 = shaped.shaper.times[1];
  const double smoothing = MoveSmoothing(shaped, 1e-5);
  EXPECT_NEAR(smoothing, 0.5 * r.acceleration * a0 * a1 * t1 * t1, 1e-9);
  EXPECT_EQ(MoveSmoothing(r, 1e-5), 0.0);
}

// Klipper's recommendation on the (vibration, smoothing) pairs its docs
// print (Measuring_Resonances.md): 2HUMP_EI; 3HUMP_EI under max_smoothing
// 0.2; MZV over the near-tied 2HUMP_EI (scores 0.002342 and 0.00234).
TEST(InputShaperTest, KlippersRuleRecommendsWhatItsDocsPrint) {
  const auto pick = [](const std::vector<std::pair<double, double>>& vs) {
    std::vector<KlipperShaperFit> fits;
    for (size_t k = 0; k < vs.size(); ++k) {
      KlipperShaperFit f;
      f.type = static_cast<ShaperType>(k + 1);
      f.vibration = vs[k].first;
      f.smoothing = vs[k].second;
      f.score = KlipperScore(f.vibration, f.smoothing);
      fits.push_back(f);
    }
    return fits[RecommendShaper(fits)].type;
  };
  // ZV, MZV, EI, 2HUMP_EI, 3HUMP_EI as printed (ZVD, absent there, at a
  // score no rule would pick).
  const auto with_zvd = [](std::vector<std::pair<double, double>> v) {
    v.insert(v.begin() + 2, {0.5, 1.0});
    return v;
  };
  EXPECT_EQ(pick(with_zvd({{0.203, 0.053}, {0.036, 0.168}, {0.049, 0.135}, {0.001, 0.264},
                           {0.0, 0.356}})),
            ShaperType::k2HumpEI);
  EXPECT_EQ(pick(with_zvd({{0.197, 0.057}, {0.036, 0.170}, {0.048, 0.139}, {0.027, 0.200},
                           {0.014, 0.155}})),
            ShaperType::k3HumpEI);
  EXPECT_EQ(pick(with_zvd({{0.132, 0.105}, {0.017, 0.150}, {0.022, 0.240}, {0.0, 0.234},
                           {0.0, 0.235}})),
            ShaperType::kMZV);
  EXPECT_NEAR(KlipperScore(0.017, 0.150), 0.150 * (std::pow(0.017, 1.5) + 0.0034 + 0.01), 1e-15);
  EXPECT_THROW(RecommendShaper({}), std::invalid_argument);
}

// On a spectrum of one lightly damped mode, every fitted shaper's remaining
// vibration is small and the frequencies sit near the mode's; an empty
// spectrum is refused.
TEST(InputShaperTest, KlippersRuleFitsASingleModeSpectrum) {
  ResonanceSpectrum spectrum;
  const double f_mode = 40.0, zeta = 0.05;
  for (double f = 5.0; f <= 133.0; f += 0.5) {
    const double r = f / f_mode;
    spectrum.frequency.push_back(f);
    spectrum.psd.push_back(1.0 / (std::pow(1 - r * r, 2) + std::pow(2 * zeta * r, 2)));
  }
  Reference move;
  move.distance = 0.1;
  move.velocity = 0.5;
  move.acceleration = 5.0;
  const KlipperShaperChoice choice = ChooseShaperAsKlipper(spectrum, move, KlipperRuleSettings{});
  ASSERT_EQ(choice.fitted.size(), 6u);
  for (const KlipperShaperFit& f : choice.fitted) {
    SCOPED_TRACE(ShaperName(f.type));
    EXPECT_LT(f.vibration, 0.2);
    EXPECT_GT(f.frequency, 0.6 * f_mode);
    EXPECT_LT(f.frequency, 1.6 * f_mode);
  }
  EXPECT_EQ(choice.shaper.type, choice.fitted[choice.recommended].type);
  EXPECT_THROW(ChooseShaperAsKlipper(ResonanceSpectrum{}, move, KlipperRuleSettings{}),
               std::invalid_argument);
}

// The frequency read off a residual vibration built by hand.
TEST(InputShaperTest, ResidualVibrationFrequencyReadsADecayingCosine) {
  MoveResponse r;
  r.move_duration = 0.2;
  r.target = 0.1;
  for (int k = 0; k <= 10000; ++k) {
    const double t = k * 1e-4;
    r.t.push_back(t);
    r.x.push_back(t < 0.2 ? 0.5 * t
                          : 0.1 + 1e-3 * std::exp(-(t - 0.2) / 0.3) * std::cos(2 * kPi * 17 * t));
  }
  EXPECT_NEAR(ResidualVibrationFrequency(r, 1e-5), 17.0, 0.2);
  EXPECT_TRUE(std::isnan(ResidualVibrationFrequency(r, 1e-2)));  // below the floor
}

Reference ReferenceFrom(const std::string& text) {
  const YAML::Node node = ParseYamlText(text, "exp.yaml");
  YamlMap map(node, "exp.yaml", "reference.");
  return ParseReference(map, ".", 0.0);
}

std::string ReferenceError(const std::string& text) {
  try {
    ReferenceFrom(text);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(InputShaperTest, ReferenceShaperKeys) {
  const Reference r = ReferenceFrom(
      "{type: trapezoid, distance: 0.1, velocity: 0.5, acceleration: 10,\n"
      " shaper: {type: mzv, frequency: 20, damping: 0.05}}\n");
  EXPECT_EQ(r.shaper.type, ShaperType::kMZV);
  EXPECT_EQ(r.shaper.frequency, 20.0);
  EXPECT_EQ(r.shaper.damping, 0.05);
  EXPECT_EQ(ReferenceFrom("{type: min_jerk, distance: 0.1, velocity: 0.5, acceleration: 10,"
                          " shaper: {type: EI, frequency: 9}}")
                .shaper.damping,
            0.1);
  EXPECT_NE(ReferenceError("{type: trapezoid, distance: 0.1, velocity: 0.5, acceleration: 10,"
                           " shaper: {type: ZVDD, frequency: 9}}")
                .find("reference.shaper.type"),
            std::string::npos);
  EXPECT_NE(ReferenceError("{type: trapezoid, distance: 0.1, velocity: 0.5, acceleration: 10,"
                           " shaper: {type: ZV, frequency: 9, damping: 1}}")
                .find("reference.shaper.damping"),
            std::string::npos);
  EXPECT_NE(ReferenceError("{type: trapezoid, distance: 0.1, velocity: 0.5, acceleration: 10,"
                           " shaper: {type: ZV}}")
                .find("reference.shaper.frequency"),
            std::string::npos);
}

std::string TuneError(const std::string& move) {
  try {
    TuneSettings t;
    ParseTuneSettings(ParseYamlText("move: " + move, "job.yaml"), "job.yaml", &t);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(InputShaperTest, TuneMoveShaperKeys) {
  TuneSettings t;
  ParseTuneSettings(ParseYamlText("move: {shapers: [ZV, mzv, 3HUMP_EI], shaper_frequency: [5, "
                                  "50], shaper_damping: [0.02, 0.2]}",
                                  "job.yaml"),
                    "job.yaml", &t);
  EXPECT_EQ(t.move.shapers, (std::vector<ShaperType>{ShaperType::kZV, ShaperType::kMZV,
                                                     ShaperType::k3HumpEI}));
  EXPECT_EQ(t.move.shaper_frequency_low, 5.0);
  EXPECT_EQ(t.move.shaper_frequency_high, 50.0);
  EXPECT_EQ(t.move.shaper_damping_low, 0.02);
  EXPECT_EQ(t.move.shaper_damping_high, 0.2);
  // Each bad block is refused naming its key.
  const std::pair<const char*, const char*> refused[] = {
      {"{shapers: [ZV, ZV]}", "tune.move.shapers"},
      {"{shapers: [none]}", "tune.move.shapers"},
      {"{shapers: [ZV], shaper_frequency: [50, 5]}", "tune.move.shaper_frequency"},
      {"{shapers: [ZV], shaper_damping: [0, 1]}", "tune.move.shaper_damping"},
      {"{shapers: [ZV], shaper_frequency: [0.01, 5]}", "tune.move.shaper_frequency"},
      {"{shaper_frequency: [5, 50]}", "tune.move.shaper_frequency"},
      {"{klipper: {min_freq: 200}}", "tune.move.klipper.max_freq"},
      {"{klipper: {hz_per_sec: 0}}", "tune.move.klipper.hz_per_sec"},
      {"{klipper: {max_freq: 10, min_freq: 5, hz_per_sec: 0.001}}", "tune.move.klipper"},
  };
  for (const auto& [text, key] : refused) {
    EXPECT_NE(TuneError(text).find(key), std::string::npos) << text;
  }
  // klipper: alone, the defaults.
  ParseTuneSettings(ParseYamlText("move: {klipper: }", "job.yaml"), "job.yaml", &t);
  EXPECT_TRUE(t.move.klipper.enabled);
  EXPECT_EQ(t.move.klipper.max_freq, 133.33);
  EXPECT_EQ(t.move.klipper.accel_per_hz, 0.075);
}

// Klipper's sweep is read by the controller every T_s: a max_freq above a
// quarter of 1/T_s (50 Hz for the X axis's 5 ms) is refused when the job
// loads, naming the key, before any fit.
TEST(InputShaperTest, KlipperMaxFreqAboveTheControllersReachIsRefusedAtLoad) {
  const std::string dir = std::string(PROJECT_SOURCE_DIR) + "/configs/jobs/tune";
  YAML::Node job = YAML::LoadFile(dir + "/x_axis_shaped.yaml");
  EXPECT_NO_THROW(ParseFitJob(job, "x_axis_shaped.yaml", dir));
  job["tune"]["move"]["klipper"]["max_freq"] = 60.0;
  try {
    ParseFitJob(job, "x_axis_shaped.yaml", dir);
    ADD_FAILURE() << "max_freq 60 Hz was accepted";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("key 'tune.move.klipper.max_freq': expected at most a quarter of the "
                        "controller's sample rate (50 Hz"),
              std::string::npos)
        << what;
  }
}

}  // namespace
}  // namespace axis
