// The canonical output channels of MODEL.md §6, their names and units.
#ifndef SIM_CHANNELS_H_
#define SIM_CHANNELS_H_

#include <optional>
#include <string>

namespace axis {

// Canonical channels, MODEL.md §6. All SI.
enum class Channel {
  kT,       // t      s     time
  kU,       // u      V     set-velocity voltage or controller output (with injection)
  kX,       // x      m     arm position y0
  kV,       // v      m/s   arm velocity y1
  kA,       // a      m/s²  arm acceleration y1'
  kTheta,   // theta  rad   motor angle y2
  kOmega,   // omega  rad/s motor angular velocity y3
  kI,       // i      A     motor current
  kTach,    // tach   V     K_t·ω
  kVc,      // vc     V     preamp output (eq. 2)
  kVm,      // vm     V     motor voltage (eq. 3)
  kFg,      // fg     N     gear force (eq. 5)
  kForce,   // force  N     drive force on the load
  kXRef,    // x_ref  m     controller reference position
  kVRef,    // v_ref  m/s   controller reference velocity
};
inline constexpr int kNumChannels = 15;

// "t", "u", "x", ... as in MODEL.md §6.
const char* ChannelName(Channel c);
// SI unit of the channel, e.g. "m/s^2" for a, on a linear axis.
const char* ChannelUnit(Channel c);
// The unit of the channel on a rotary axis (`rotary` true, MODEL.md §4): the
// load's channels x, v, a, x_ref, v_ref in rad, rad/s, rad/s², fg and force
// in N·m; the others as ChannelUnit. Never throws.
std::string ChannelUnit(Channel c, bool rotary);
// A linear load's unit as the rotary load's: "m" → "rad", "N" → "N*m",
// "kg" → "kg*m^2", factor by factor ("N*s/m" → "N*m*s/rad", "m/s^2" →
// "rad/s^2"); other factors unchanged. Never throws.
std::string RotaryLoadUnit(const std::string& linear_unit);
// The channel called `name`, or nullopt.
std::optional<Channel> ParseChannel(const std::string& name);
// "t, u, x, ..." for error messages.
std::string ChannelNameList();

}  // namespace axis

#endif  // SIM_CHANNELS_H_
