#include "sim/channels.h"

#include <array>

namespace axis {
namespace {

struct ChannelInfo {
  const char* name;
  const char* unit;
};

constexpr std::array<ChannelInfo, kNumChannels> kChannels = {{
    {"t", "s"},
    {"u", "V"},
    {"x", "m"},
    {"v", "m/s"},
    {"a", "m/s^2"},
    {"theta", "rad"},
    {"omega", "rad/s"},
    {"i", "A"},
    {"tach", "V"},
    {"vc", "V"},
    {"vm", "V"},
    {"fg", "N"},
    {"force", "N"},
    {"x_ref", "m"},
    {"v_ref", "m/s"},
}};

}  // namespace

const char* ChannelName(Channel c) {
  return kChannels[static_cast<int>(c)].name;
}

const char* ChannelUnit(Channel c) {
  return kChannels[static_cast<int>(c)].unit;
}

std::string RotaryLoadUnit(const std::string& linear_unit) {
  std::string out;
  size_t start = 0;
  while (start <= linear_unit.size()) {
    const size_t end = linear_unit.find_first_of("*/", start);
    const std::string factor =
        linear_unit.substr(start, end == std::string::npos ? std::string::npos : end - start);
    const size_t caret = factor.find('^');
    const std::string base = factor.substr(0, caret);
    const std::string power = caret == std::string::npos ? "" : factor.substr(caret);
    if (base == "m") {
      out += "rad" + power;
    } else if (base == "N" && power.empty()) {
      out += "N*m";
    } else if (base == "kg" && power.empty()) {
      out += "kg*m^2";
    } else {
      out += factor;
    }
    if (end == std::string::npos) break;
    out += linear_unit[end];
    start = end + 1;
  }
  return out;
}

std::string ChannelUnit(Channel c, bool rotary) {
  const char* unit = ChannelUnit(c);
  if (!rotary) return unit;
  switch (c) {
    case Channel::kX: case Channel::kV: case Channel::kA: case Channel::kFg:
    case Channel::kForce: case Channel::kXRef: case Channel::kVRef:
      return RotaryLoadUnit(unit);
    default:
      return unit;
  }
}

std::optional<Channel> ParseChannel(const std::string& name) {
  for (int c = 0; c < kNumChannels; ++c) {
    if (name == kChannels[c].name) return static_cast<Channel>(c);
  }
  return std::nullopt;
}

std::string ChannelNameList() {
  std::string out;
  for (int c = 0; c < kNumChannels; ++c) {
    if (c) out += ", ";
    out += kChannels[c].name;
  }
  return out;
}

}  // namespace axis
