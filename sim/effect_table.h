// The effects a model can switch on (MODEL.md §7) and how the tool names
// them: the dynamic effects, the generator-only forces, the sensor effects
// by channel, and the tests on an effect's name that the loaders and the
// discovery loop share.
#ifndef SIM_EFFECT_TABLE_H_
#define SIM_EFFECT_TABLE_H_

#include <string>
#include <vector>

#include "sim/axis_model.h"
#include "sim/axis_params.h"

namespace axis {

// The dynamic effects of MODEL.md §7: config name, parameter names (in
// VisitParams naming) and the switch in EffectSwitches. The one list of them.
struct EffectInfo {
  const char* name;
  std::vector<const char*> params;
  bool EffectSwitches::*flag;
};
const std::vector<EffectInfo>& DynamicEffectTable();

// Forces outside MODEL.md §7 that a model config may switch on to generate
// data (issue 10: the discovery loop's verdict on a force its library
// lacks), under `effects:` like the §7 ones:
//   friction_patch: {F_pt: N, x_pt0: m, x_pt1: m, w_pt: m}  F_pt·sgn_ε(v)
//       for x_pt0 < x < x_pt1, edges smoothed over w_pt (> 0); x_pt1 > x_pt0.
//   quadratic_drag: {C_d: N*s^2/m^2}                        C_d·v·|v|
//   position_ripple: {F_rp: N, lambda_rp: m, phi_rp: rad}
//       F_rp·sin(2π·x/λ_rp + φ_rp): periodic in the load position, λ_rp > 0.
//   velocity_bump: {F_vb: N, v_vb: m/s, w_vb: m/s}
//       F_vb·exp(−((|v| − v_vb)/w_vb)²)·sgn_ε(v): friction peaking at one
//       speed (issue 15's force-map tests), v_vb ≥ 0, w_vb > 0.
// Not effects in the sense of IsEffectName: never discovery candidates, and
// a fit job cannot name them in discover.candidates (sim/axis_model.h has
// their equations).
const std::vector<EffectInfo>& GeneratorOnlyEffectTable();

// Their names for messages: "friction_patch, quadratic_drag, position_ripple,
// velocity_bump".
std::string GeneratorOnlyEffectNameList();

// The effects switched on in `s`, as the discovery loop names them: the
// DynamicEffectTable names in its order, then sensor_delay.<channel> and
// sensor_bias.<channel> in channel order, then force_map.<kind> (x,
// x_friction or v; sim/force_map.h). Never throws.
std::vector<std::string> EnabledEffectNames(const AxisStructure& s);

// Whether `name` names one effect the way the discovery loop does: a
// DynamicEffectTable name ("coulomb"), or a SensorEffectTable name with a
// MODEL.md §6 channel ("sensor_delay.a"); with `allow_bare_sensor` also
// the sensor effect's name alone ("sensor_delay": every channel).
bool IsEffectName(const std::string& name, bool allow_bare_sensor = false);

// Whether an effect name (IsEffectName, or "force_map.x" style) belongs to
// the sensor front end (MODEL.md §6: sensor_delay, sensor_bias,
// sensor_lowpass, sensor_lowpass2, with or without a channel; and the
// accelerometer's sampling convention as the discovery loop names its
// change, "accelerometer.instant" or "accelerometer.period_mean") rather
// than to the plant. The discovery report lists the two apart. Never throws.
bool IsFrontEndEffect(const std::string& name);

// The list of effect names for messages: "coulomb, stribeck, …,
// sensor_delay[.channel], sensor_bias[.channel], …".
std::string EffectNameList();

}  // namespace axis

#endif  // SIM_EFFECT_TABLE_H_
