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
