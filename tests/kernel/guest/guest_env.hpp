#pragma once
// What the guest's /init found and set up, handed over in environment
// variables (tests/kernel/guest-init.sh). A test whose device is missing
// skips with the reason /init gave (SW_*_SKIP), never passes silently.
#include <cstdint>
#include <cstdlib>
#include <string>

#include <gtest/gtest.h>

#include "spinewatch/frames/clock.hpp"

namespace spinewatch::kernel_test {

inline std::string env_or_empty(const char* name) {
  const char* value = std::getenv(name);
  return value ? value : "";
}

// The named variables, or a skip reason: the area's SW_<AREA>_SKIP when /init
// set one, else which variable is missing.
inline std::string missing_reason(const char* skip_var, std::initializer_list<const char*> needed) {
  if (const std::string why = env_or_empty(skip_var); !why.empty()) return why;
  for (const char* name : needed) {
    if (env_or_empty(name).empty()) return std::string(name) + " is not set (run inside the kernel VM: tests/kernel/kernel-vm)";
  }
  return "";
}

#define SW_REQUIRE_ENV(skip_var, ...)                                                 \
  do {                                                                                \
    if (const std::string why_ = ::spinewatch::kernel_test::missing_reason(skip_var, {__VA_ARGS__}); \
        !why_.empty())                                                                \
      GTEST_SKIP() << why_;                                                           \
  } while (false)

}  // namespace spinewatch::kernel_test
