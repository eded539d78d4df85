// Fails the current test (never skips it) when vcan0 is missing: the vcan tests run inside UML.
// For the vcan test programs: they link ldoem_test_support_vcan, which brings the emulator's io
// library (io::check_can_interface).
#pragma once

#include <gtest/gtest.h>

#include "ldoem/io/can_interface.hpp"

#define LDOEM_REQUIRE_VCAN0()                                                                 \
  do {                                                                                        \
    auto vcan = ::ldoem::io::check_can_interface("vcan0");                                    \
    ASSERT_TRUE(vcan) << vcan.error().message()                                               \
                      << " (vcan tests run inside UML: scripts/uml/run.sh -- ctest -L vcan)"; \
  } while (false)
