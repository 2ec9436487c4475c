// Strict loading of model configs and experiment files: every committed
// config loads, and bad input gives a message naming the file, the line and
// the key and saying what was expected.
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "sim/config.h"
#include "sim/preflight.h"
#include "io/yaml_util.h"
#include "tests/test_files.h"

namespace axis {
namespace {

const std::string kRoot = PROJECT_SOURCE_DIR;

using testing_files::WriteTemp;

// The message of the std::invalid_argument thrown by `load`, or "" if none.
template <typename F>
std::string ErrorOf(F&& load) {
  try {
    load();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

// A valid experiment around the X axis config, with `extra` appended.
std::string Experiment(const std::string& extra,
                       const std::string& input = "input: {type: step, amplitude: 1}\n") {
  return "model: " + kRoot + "/configs/axes/x_axis.yaml\n"
         "duration: 0.01\nchannels: [v]\n" + input + extra;
}

TEST(ConfigTest, EveryCommittedAxisConfigLoads) {
  for (const char* name : {"x_axis", "y_axis", "z_axis", "wrist_pitch",
                           "wrist_roll", "emps"}) {
    SCOPED_TRACE(name);
    const AxisConfig c = LoadAxisConfig(kRoot + "/configs/axes/" + name + ".yaml");
    EXPECT_EQ(c.name, name);
  }
}

TEST(ConfigTest, XAxisHasThePapersValues) {
  const AxisConfig c = LoadAxisConfig(kRoot + "/configs/axes/x_axis.yaml");
  const AxisParams<double> paper;  // defaults are MODEL.md §2
  VisitParams([&](const char* name, const char*, const double& got,
                  const double& want) { EXPECT_EQ(got, want) << name; },
              c.params, paper);
  EXPECT_EQ(c.structure.amplifier, Amplifier::kAnalogVelocityLoop);
  EXPECT_EQ(c.structure.coupling, Coupling::kGear);
  EXPECT_TRUE(c.has_controller);
  EXPECT_EQ(c.controller.T_s, 0.005);
  EXPECT_EQ(c.controller.T_track, 0.08);
}

TEST(ConfigTest, EmpsConfigIsForceSourceRigidWithItsController) {
  const AxisConfig c = LoadAxisConfig(kRoot + "/configs/axes/emps.yaml");
  EXPECT_EQ(c.structure.amplifier, Amplifier::kForceSource);
  EXPECT_EQ(c.structure.coupling, Coupling::kRigid);
  EXPECT_NEAR(c.params.g_F, 35.15065188248547, 1e-12);
  EXPECT_NEAR(c.controller.G_p, 160.18 * 243.45, 1e-6);
  EXPECT_EQ(c.controller.G_v, 243.45);
  EXPECT_EQ(c.controller.alpha, 0.5);
  EXPECT_EQ(c.controller.T_s, 0.001);
}

TEST(ConfigTest, ZAxisCarriesGravityAsALoadOffset) {
  const AxisConfig c = LoadAxisConfig(kRoot + "/configs/axes/z_axis.yaml");
  EXPECT_TRUE(c.structure.effects.load_offset);
  EXPECT_NEAR(c.params.F_0, c.params.M * 9.81, 1e-9);
}

TEST(ConfigTest, EveryCommittedExperimentLoads) {
  for (const char* name : {"x_step_10V", "x_move_1m", "x_linear_tp4.74",
                           "x_linear_tp0.195"}) {
    SCOPED_TRACE(name);
    EXPECT_NO_THROW(LoadExperiment(kRoot + "/configs/experiments/" + name + ".yaml"));
  }
}

// Found by fuzz/experiment_fuzz.cc: `model:` naming a directory escaped as
// std::ios_base::failure (exit 1, not 2).
TEST(ConfigTest, ModelThatIsADirectoryIsRefused) {
  const std::string path = WriteTemp("dir_model.yaml",
                                     "model: " + kRoot + "/configs/axes\nduration: 1\n");
  const std::string msg = ErrorOf([&] { LoadExperiment(path); });
  EXPECT_NE(msg.find(kRoot + "/configs/axes: cannot read the file: expected a file, got a "
                             "directory"),
            std::string::npos)
      << msg;
}

TEST(ConfigTest, UnknownKeyNamesFileLineAndKey) {
  const std::string path = WriteTemp("unknown.yaml", Experiment("colour: red\n"));
  const std::string msg = ErrorOf([&] { LoadExperiment(path); });
  EXPECT_NE(msg.find(path + ":5:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("'colour'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("expected one of the known keys"), std::string::npos) << msg;
}

TEST(ConfigTest, UnknownNestedKeyNamesItsPath) {
  const std::string path = WriteTemp(
      "nested.yaml", Experiment("", "input: {type: step, amplitude: 1, hight: 2}\n"));
  const std::string msg = ErrorOf([&] { LoadExperiment(path); });
  EXPECT_NE(msg.find("key 'input.hight'"), std::string::npos) << msg;
}

// A key given twice is refused with both lines (yaml-cpp keeps both and a
// loader would read one of them): at the top level and inside a mapping.
TEST(ConfigTest, RepeatedKeyIsRefusedWithBothLines) {
  const std::string top = WriteTemp("twice.yaml", Experiment("duration: 0.02\n"));
  std::string msg = ErrorOf([&] { LoadExperiment(top); });
  EXPECT_NE(msg.find(top + ":5: key 'duration'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("expected each key once in a mapping, got 'duration' again (first on line 2)"),
            std::string::npos)
      << msg;
  const std::string nested = WriteTemp(
      "twice_nested.yaml", Experiment("", "input:\n  type: step\n  amplitude: 1\n  amplitude: 2\n"));
  msg = ErrorOf([&] { LoadExperiment(nested); });
  EXPECT_NE(msg.find(nested + ":7: key 'input.amplitude'"), std::string::npos) << msg;
}

// Every YAML file goes through LoadYamlFile (issue 46): a model config with
// a second document (ignored before), or a merge key (not applied), or
// bytes that are not UTF-8 text, is refused naming the file and line.
TEST(ConfigTest, SecondDocumentMergeKeyAndNonUtf8AreRefused) {
  std::ifstream in(kRoot + "/configs/axes/x_axis.yaml");
  const std::string model((std::istreambuf_iterator<char>(in)), {});
  const int lines = static_cast<int>(std::count(model.begin(), model.end(), '\n'));
  std::string path = WriteTemp("two.yaml", model + "---\nname: other\n");
  std::string msg = ErrorOf([&] { LoadAxisConfig(path); });
  EXPECT_EQ(msg.rfind(path + ":" + std::to_string(lines + 1) +
                          ": expected one YAML document, got a second one",
                      0),
            0u)
      << msg;
  path = WriteTemp("merge.yaml", Experiment("", "defaults: &d {type: step}\ninput:\n  <<: *d\n  "
                                                "amplitude: 1\n"));
  msg = ErrorOf([&] { LoadExperiment(path); });
  EXPECT_NE(msg.find(path + ":6: key 'input.<<': expected no YAML merge key"), std::string::npos)
      << msg;
  path = WriteTemp("latin1.yaml", Experiment("title: caf\xe9\n"));
  msg = ErrorOf([&] { LoadExperiment(path); });
  EXPECT_NE(msg.find(path + ":5: expected UTF-8 text, got byte 0xE9 at byte offset"),
            std::string::npos)
      << msg;
}

// Found by fuzz/model_config_fuzz.cc (a CI run): yaml-cpp 0.7's LoadAll
// never returns on a stray ',' at the top level (an empty document forever,
// the ',' never consumed). ParseYamlText asks for two documents at most and
// refuses the text as invalid YAML, without naming a '---' that is not there.
TEST(ConfigTest, StrayFlowIndicatorIsRefusedWithoutHanging) {
  for (const char* text : {",", ",,name: x", "name: x\n,\n"}) {
    const std::string msg = ErrorOf([&] { ParseYamlText(text, "stray.yaml"); });
    EXPECT_EQ(msg.rfind("stray.yaml", 0), 0u) << msg;
    EXPECT_NE(msg.find("invalid YAML"), std::string::npos) << text << ": " << msg;
  }
  EXPECT_NO_THROW(ParseYamlText("name: x\n...\n", "end.yaml"));
}

// The memory check: nothing below half the physical memory, a clear
// message above it.
TEST(ConfigTest, MemoryCheckRefusesMoreThanHalfThePhysicalMemory) {
  const double physical = PhysicalMemoryBytes();
  ASSERT_GT(physical, 0.0);
  EXPECT_NO_THROW(CheckMemory(0.4 * physical, "f.yaml", "the fit", "advice"));
  const std::string msg = ErrorOf([&] { CheckMemory(0.6 * physical, "f.yaml", "the fit", "advice"); });
  EXPECT_NE(msg.find("f.yaml: expected the fit to fit in memory"), std::string::npos) << msg;
  EXPECT_NE(msg.find(": advice"), std::string::npos) << msg;
}

// Found by fuzzing the experiment loader (scripts/fuzz, 10-minute run): a
// PRBS with bit_time 1e-11 s over 4 s asked for a table of 4·10¹¹ bits
// (libFuzzer timeout at 3.5 GB). Refused before allocating, naming the key;
// 10⁸ bits is kMaxPrbsBits (sim/input_signal.h).
TEST(ConfigTest, PrbsWithTooManyBitsIsRefused) {
  const std::string head = "model: " + kRoot + "/configs/axes/x_axis.yaml\n"
                           "duration: 4.0\nchannels: [u]\n";
  const std::string path = WriteTemp(
      "prbs.yaml", head + "input: {type: prbs, amplitude: 4, bit_time: 00.00000000001, "
                          "order: 8, seed: 1}\n");
  const std::string msg = ErrorOf([&] { LoadExperiment(path); });
  EXPECT_NE(msg.find("prbs.yaml:4"), std::string::npos) << msg;
  EXPECT_NE(msg.find("input.bit_time"), std::string::npos) << msg;
  EXPECT_NE(msg.find("expected a PRBS of at most 1e+08 bits, got 4e+11 bits"), std::string::npos)
      << msg;
  // The same record with 0.1 ms bits (40 001 bits) loads.
  std::ofstream(path) << head << "input: {type: prbs, amplitude: 4, bit_time: 1.0e-4, order: 8}\n";
  EXPECT_EQ(LoadExperiment(path).drive.input.times.size(), 40001u);
}

TEST(ConfigTest, MissingKeyIsNamed) {
  const std::string path = WriteTemp(
      "missing.yaml", "model: " + kRoot + "/configs/axes/x_axis.yaml\n"
                      "channels: [v]\ninput: {type: step, amplitude: 1}\n");
  const std::string msg = ErrorOf([&] { LoadExperiment(path); });
  EXPECT_NE(msg.find("key 'duration'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("required"), std::string::npos) << msg;
}

TEST(ConfigTest, MissingModelParameterIsNamed) {
  std::ifstream in(kRoot + "/configs/axes/x_axis.yaml");
  std::string text((std::istreambuf_iterator<char>(in)), {});
  text.replace(text.find("  M: 146"), 8, "");
  const std::string path = WriteTemp("no_mass.yaml", text);
  const std::string msg = ErrorOf([&] { LoadAxisConfig(path); });
  EXPECT_NE(msg.find("key 'parameters.M'"), std::string::npos) << msg;
}

TEST(ConfigTest, WrongTypeSaysWhatWasExpected) {
  const std::string path = WriteTemp("type.yaml", Experiment("step: fast\n"));
  const std::string msg = ErrorOf([&] { LoadExperiment(path); });
  EXPECT_NE(msg.find("key 'step': expected a finite positive number, got 'fast'"),
            std::string::npos) << msg;
}

TEST(ConfigTest, NonPositiveMassInertiaAndTimeConstantsAreRejected) {
  for (const char* name : {"M", "J_m", "T_p", "T_r", "L"}) {
    SCOPED_TRACE(name);
    const std::string path = WriteTemp(
        std::string("neg_") + name + ".yaml",
        Experiment(std::string("set: {") + name + ": -1}\n"));
    const std::string msg = ErrorOf([&] { LoadExperiment(path); });
    EXPECT_NE(msg.find(path), std::string::npos) << msg;
    EXPECT_NE(msg.find(std::string("'") + name + "'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("expected a finite positive number, got -1"), std::string::npos)
        << msg;
  }
}

TEST(ConfigTest, UnknownEffectNameListsTheKnownOnes) {
  const std::string path =
      WriteTemp("effect.yaml", Experiment("effects: {magic_friction: {F: 1}}\n"));
  const std::string msg = ErrorOf([&] { LoadExperiment(path); });
  EXPECT_NE(msg.find("key 'effects.magic_friction'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("coulomb"), std::string::npos) << msg;
}

TEST(ConfigTest, EffectsAreParsedWithTheirParameters) {
  const std::string path = WriteTemp(
      "effects_ok.yaml",
      Experiment("effects:\n  coulomb: {F_c: 30}\n  cogging: {A_cog: 0.02, "
                 "phi_cog: 0.1, N_cog: 6}\n  sensor_delay: {a: 0.002}\n"
                 "  sensor_bias: {tach: 0.01}\n"));
  const ExperimentConfig e = LoadExperiment(path);
  EXPECT_TRUE(e.model.structure.effects.coulomb);
  EXPECT_EQ(e.model.params.F_c, 30.0);
  EXPECT_TRUE(e.model.structure.effects.cogging);
  EXPECT_EQ(e.model.structure.N_cog, 6);
  EXPECT_EQ(e.model.params.A_cog, 0.02);
  EXPECT_TRUE(e.model.structure.sensors.delay[static_cast<int>(Channel::kA)]);
  EXPECT_EQ(e.model.params.tau_d[static_cast<int>(Channel::kA)], 0.002);
  EXPECT_EQ(e.model.params.b[static_cast<int>(Channel::kTach)], 0.01);
}

// The Stribeck shape exponent (MODEL.md §7 stribeck_shape): declared by the
// stribeck block's delta_st or by its own block, written back as the
// latter (also where a job freed δ with the flag off), refused without
// the Stribeck term it shapes.
TEST(ConfigTest, TheStribeckShapeIsDeclaredWrittenBackAndNeedsStribeck) {
  const ExperimentConfig e = LoadExperiment(WriteTemp(
      "shape.yaml", Experiment("effects:\n  coulomb: {F_c: 30}\n"
                               "  stribeck: {F_st: 50, v_st: 0.05, delta_st: 1}\n")));
  EXPECT_TRUE(e.model.structure.effects.stribeck_shape);
  EXPECT_EQ(e.model.params.delta_st, 1.0);
  const std::string text = AxisConfigToYaml(e.model);
  EXPECT_NE(text.find("stribeck_shape"), std::string::npos) << text;
  const AxisConfig back = LoadAxisConfig(WriteTemp("shape_back.yaml", text));
  EXPECT_TRUE(back.structure.effects.stribeck_shape);
  EXPECT_EQ(back.params.delta_st, 1.0);
  AxisConfig freed = e.model;  // δ fitted by a job, the flag off
  freed.structure.effects.stribeck_shape = false;
  freed.params.delta_st = 1.3;
  const AxisConfig freed_back =
      LoadAxisConfig(WriteTemp("freed_back.yaml", AxisConfigToYaml(freed)));
  EXPECT_EQ(freed_back.params.delta_st, 1.3);
  const ExperimentConfig gaussian = LoadExperiment(WriteTemp(
      "gaussian.yaml", Experiment("effects:\n  coulomb: {F_c: 30}\n"
                                  "  stribeck: {F_st: 50, v_st: 0.05}\n")));
  EXPECT_FALSE(gaussian.model.structure.effects.stribeck_shape);
  EXPECT_EQ(AxisConfigToYaml(gaussian.model).find("stribeck_shape"), std::string::npos);
  const std::string alone = ErrorOf([&] {
    LoadExperiment(WriteTemp("shape_alone.yaml",
                             Experiment("effects:\n  stribeck_shape: {delta_st: 1}\n")));
  });
  EXPECT_NE(alone.find("key 'effects.stribeck_shape': expected the Stribeck term"),
            std::string::npos)
      << alone;
}

// Forces outside MODEL.md §7 (issue 10) load for generating data, round
// trip through AxisConfigToYaml, and are no discovery candidates.
TEST(ConfigTest, GeneratorOnlyForcesLoadButAreNotEffectsOfTheLibrary) {
  const std::string path = WriteTemp(
      "generator_only.yaml",
      Experiment("effects:\n  friction_patch: {F_pt: 40, x_pt0: 0.01, x_pt1: 0.03, "
                 "w_pt: 0.002}\n  quadratic_drag: {C_d: 500}\n"
                 "  position_ripple: {F_rp: 30, lambda_rp: 0.05, phi_rp: 0.2}\n"));
  const ExperimentConfig e = LoadExperiment(path);
  EXPECT_TRUE(e.model.structure.effects.friction_patch);
  EXPECT_TRUE(e.model.structure.effects.quadratic_drag);
  EXPECT_EQ(e.model.params.F_pt, 40.0);
  EXPECT_EQ(e.model.params.x_pt0, 0.01);
  EXPECT_EQ(e.model.params.x_pt1, 0.03);
  EXPECT_EQ(e.model.params.w_pt, 0.002);
  EXPECT_EQ(e.model.params.C_d, 500.0);
  EXPECT_TRUE(e.model.structure.effects.position_ripple);
  EXPECT_EQ(e.model.params.F_rp, 30.0);
  EXPECT_EQ(e.model.params.lambda_rp, 0.05);
  EXPECT_EQ(e.model.params.phi_rp, 0.2);
  const AxisConfig back =
      LoadAxisConfig(WriteTemp("generator_only_back.yaml", AxisConfigToYaml(e.model)));
  EXPECT_TRUE(back.structure.effects.friction_patch);
  EXPECT_TRUE(back.structure.effects.quadratic_drag);
  EXPECT_EQ(back.params.x_pt1, 0.03);
  EXPECT_EQ(back.params.C_d, 500.0);
  EXPECT_TRUE(back.structure.effects.position_ripple);
  EXPECT_EQ(back.params.lambda_rp, 0.05);
  EXPECT_FALSE(IsEffectName("friction_patch"));
  EXPECT_FALSE(IsEffectName("quadratic_drag"));
  EXPECT_FALSE(IsEffectName("position_ripple"));
  // A ripple needs a positive period.
  const std::string zero_period = ErrorOf([&] {
    LoadExperiment(WriteTemp("ripple_period.yaml",
                             Experiment("effects:\n  position_ripple: {F_rp: 30, lambda_rp: 0, "
                                        "phi_rp: 0}\n")));
  });
  EXPECT_NE(zero_period.find("key 'effects.position_ripple.lambda_rp'"), std::string::npos)
      << zero_period;
  // A patch that ends where it starts is refused, naming the key.
  const std::string bad = WriteTemp(
      "patch_order.yaml",
      Experiment("effects:\n  friction_patch: {F_pt: 40, x_pt0: 0.03, x_pt1: 0.03, "
                 "w_pt: 0.002}\n"));
  const std::string msg = ErrorOf([&] { LoadExperiment(bad); });
  EXPECT_NE(msg.find("key 'effects.friction_patch.x_pt1'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("expected a patch end above x_pt0"), std::string::npos) << msg;
  // The list of known effects names them apart from the library.
  const std::string unknown =
      ErrorOf([&] { LoadExperiment(WriteTemp("effect2.yaml", Experiment("effects: {x: {}}\n"))); });
  EXPECT_NE(unknown.find("to generate data, friction_patch, quadratic_drag, position_ripple"),
            std::string::npos)
      << unknown;
}

TEST(ConfigTest, MissingDataColumnIsNamed) {
  const std::string csv = WriteTemp("data.csv", "t,u\n0,1\n0.001,2\n");
  const std::string path = WriteTemp(
      "column.yaml",
      Experiment("", "input: {type: column, file: " + csv + ", column: volts}\n"));
  const std::string msg = ErrorOf([&] { LoadExperiment(path); });
  EXPECT_NE(msg.find("key 'input.column'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("'volts'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("t, u"), std::string::npos) << msg;
}

TEST(ConfigTest, UnknownSetParameterIsNamed) {
  const std::string path = WriteTemp("set.yaml", Experiment("set: {V_X: 3}\n"));
  const std::string msg = ErrorOf([&] { LoadExperiment(path); });
  EXPECT_NE(msg.find("key 'set.V_X'"), std::string::npos) << msg;
}

TEST(ConfigTest, InputAndReferenceAreExclusive) {
  const std::string path = WriteTemp(
      "both.yaml",
      Experiment("reference: {type: trapezoid, distance: 1, velocity: 1, "
                 "acceleration: 1}\n"));
  const std::string msg = ErrorOf([&] { LoadExperiment(path); });
  EXPECT_NE(msg.find("exactly one of 'input'"), std::string::npos) << msg;
}

TEST(ConfigTest, OutputPeriodMustBeWholeSteps) {
  const std::string path = WriteTemp("grid.yaml", Experiment("output_rate: 3000\n"));
  const std::string msg = ErrorOf([&] { LoadExperiment(path); });
  EXPECT_NE(msg.find("whole number"), std::string::npos) << msg;
}

TEST(ConfigTest, SetArgumentOverridesAndValidates) {
  AxisConfig c = LoadAxisConfig(kRoot + "/configs/axes/x_axis.yaml");
  ApplySetArgument(&c, "V_L=3.1");
  EXPECT_EQ(c.params.V_L, 3.1);
  EXPECT_NE(ErrorOf([&] { ApplySetArgument(&c, "M=0"); })
                .find("parameter 'M': expected a finite positive number, got 0"),
            std::string::npos);
  EXPECT_NE(ErrorOf([&] { ApplySetArgument(&c, "Q=1"); }).find("got 'Q'"),
            std::string::npos);
  EXPECT_NE(ErrorOf([&] { ApplySetArgument(&c, "V_L"); }).find("NAME=VALUE"),
            std::string::npos);
  EXPECT_NE(ErrorOf([&] { ApplySetArgument(&c, "V_L=abc"); }).find("'abc'"),
            std::string::npos);
}

// Numbers are finite unless the key's range allows .inf (V_L, "no preamp
// limit"): an infinite scale, offset, amplitude, noise σ, delay or
// parameter is refused at load, naming its key, where it used to load and
// simulate NaN (or fail naming the output file).
TEST(ConfigTest, InfiniteNumbersAreRefusedNamingTheKey) {
  const std::string csv = WriteTemp("inf_input.csv", "t,u\n0,1\n0.01,2\n");
  const std::string column = "input: {type: column, file: " + csv + ", column: u, ";
  struct Case {
    std::string input, extra, key, expected;
  };
  const Case cases[] = {
      {column + "scale: .inf}\n", "", "input.scale", "a finite number, got '.inf'"},
      {column + "offset: -.inf}\n", "", "input.offset", "a finite number, got '-.inf'"},
      {"input: {type: sine, amplitude: .inf, frequency: 1}\n", "", "input.amplitude",
       "a finite number, got '.inf'"},
      {"input: {type: step, amplitude: 1, start: .inf}\n", "", "input.start",
       "a finite number >= 0, got '.inf'"},
      {"", "noise: {v: .inf}\n", "noise.v", "a finite number >= 0, got '.inf'"},
      {"", "effects: {sensor_delay: {v: .inf}}\n", "effects.sensor_delay.v",
       "a finite number, got '.inf'"},
      {"", "effects: {sensor_lowpass: {v: .inf}}\n", "effects.sensor_lowpass.v",
       "a finite number >= 0, got '.inf'"},
      {"", "effects: {coulomb: {F_c: -.inf}}\n", "effects.coulomb.F_c",
       "a finite number, got '-.inf'"},
      {"", "initial_state: {y0: .inf}\n", "initial_state.y0", "a finite number, got '.inf'"},
      {"", "set: {B_a: .inf}\n", "set.B_a", "a finite number, got '.inf'"},
      {"", "set: {V_L: -1}\n", "set.V_L", "a positive number or .inf, got '-1'"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.key);
    const std::string path =
        WriteTemp("inf.yaml", c.input.empty() ? Experiment(c.extra) : Experiment(c.extra, c.input));
    const std::string msg = ErrorOf([&] { LoadExperiment(path); });
    EXPECT_NE(msg.find(path + ":"), std::string::npos) << msg;
    EXPECT_NE(msg.find("key '" + c.key + "': expected " + c.expected), std::string::npos) << msg;
  }
  const std::string model = WriteTemp(
      "inf_model.yaml", "name: m\namplifier: force_source\ncoupling: rigid\n"
                        "parameters: {g_F: 1, M: .inf, B_a: 1}\n");
  EXPECT_NE(ErrorOf([&] { LoadAxisConfig(model); })
                .find("key 'parameters.M': expected a finite positive number, got '.inf'"),
            std::string::npos);
  // V_L's documented .inf still loads, from set: and from --set.
  const ExperimentConfig no_limit =
      LoadExperiment(WriteTemp("inf_vl.yaml", Experiment("set: {V_L: .inf}\n")));
  EXPECT_EQ(no_limit.model.params.V_L, std::numeric_limits<double>::infinity());
  AxisConfig c = LoadAxisConfig(kRoot + "/configs/axes/x_axis.yaml");
  ApplySetArgument(&c, "V_L=inf");
  EXPECT_EQ(c.params.V_L, std::numeric_limits<double>::infinity());
  EXPECT_NE(ErrorOf([&] { ApplySetArgument(&c, "B_a=inf"); })
                .find("--set B_a=inf: parameter 'B_a': expected a finite number >= 0, got inf"),
            std::string::npos);
}

TEST(ConfigTest, ForceSourceNeedsRigidCoupling) {
  std::ifstream in(kRoot + "/configs/axes/emps.yaml");
  std::string text((std::istreambuf_iterator<char>(in)), {});
  text.replace(text.find("coupling: rigid"), 15, "coupling: gear\n");
  text.insert(text.find("parameters:") + 12, "  H: 0\n  k_g: 1\n  b_g: 1\n");
  const std::string path = WriteTemp("emps_gear.yaml", text);
  const std::string msg = ErrorOf([&] { LoadAxisConfig(path); });
  EXPECT_NE(msg.find("expected rigid"), std::string::npos) << msg;
}

// current_loop: full (default) or quasi_steady, the latter only where there
// is a current loop; a misspelt value names the choices.
TEST(ConfigTest, CurrentLoopKey) {
  const std::string x_axis = kRoot + "/configs/axes/x_axis.yaml";
  EXPECT_EQ(LoadAxisConfig(x_axis).structure.current_loop, CurrentLoop::kFull);
  std::ifstream in(x_axis);
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  const auto with = [&](const std::string& line, const std::string& name) {
    std::string t = text;
    t.insert(t.find("coupling:"), line + "\n");
    return WriteTemp(name, t);
  };
  EXPECT_EQ(LoadAxisConfig(with("current_loop: quasi_steady", "qs.yaml")).structure.current_loop,
            CurrentLoop::kQuasiSteady);
  const std::string typo = ErrorOf([&] { LoadAxisConfig(with("current_loop: quasi", "qs_typo.yaml")); });
  EXPECT_NE(typo.find("current_loop"), std::string::npos) << typo;
  EXPECT_NE(typo.find("quasi_steady"), std::string::npos) << typo;
  std::string emps;
  {
    std::ifstream e(kRoot + "/configs/axes/emps.yaml");
    emps.assign((std::istreambuf_iterator<char>(e)), {});
  }
  emps.insert(emps.find("coupling:"), "current_loop: quasi_steady\n");
  const std::string msg = ErrorOf([&] { LoadAxisConfig(WriteTemp("emps_qs.yaml", emps)); });
  EXPECT_NE(msg.find("'current_loop': expected full"), std::string::npos) << msg;
}

// model_discovered.yaml is written by AxisConfigToYaml: every parameter,
// including the sgn_ε widths and effect parameters, reads back unchanged.
TEST(ConfigTest, AxisConfigYamlRoundTrip) {
  AxisConfig config = LoadAxisConfig(kRoot + "/configs/axes/x_axis.yaml");
  config.params.v_eps = 2.5e-3;
  config.params.omega_eps = 0.4;
  config.structure.effects.coulomb = true;
  config.structure.current_loop = CurrentLoop::kQuasiSteady;
  config.params.F_c = 12.5;
  const AxisConfig back =
      LoadAxisConfig(WriteTemp("round_trip.yaml", AxisConfigToYaml(config)));
  EXPECT_TRUE(back.structure.effects.coulomb);
  EXPECT_EQ(back.structure.current_loop, CurrentLoop::kQuasiSteady);
  AxisParams<double> a = config.params, b = back.params;
  std::vector<double> values_a, values_b;
  VisitParams([&](const char*, const char*, double& v) { values_a.push_back(v); }, a);
  VisitParams([&](const char*, const char*, double& v) { values_b.push_back(v); }, b);
  ASSERT_EQ(values_a.size(), values_b.size());
  for (size_t k = 0; k < values_a.size(); ++k) EXPECT_EQ(values_a[k], values_b[k]) << k;
}

}  // namespace
}  // namespace axis
