// The configuration loader on arbitrary bytes: it may only accept or throw
// ConfigError, and whatever it accepts must validate, print and load back equal.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "daemon/config.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace tumble::daemon;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const DaemonConfig config = load_config(text, "fuzz.yaml");
    validate(config);
    if (!(load_config(to_yaml(config), "printed") == config)) __builtin_trap();
  } catch (const ConfigError&) {
  }
  return 0;
}
