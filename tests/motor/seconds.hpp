// The head tests check closed forms in SI units: a SimTime as seconds.
#pragma once

#include <ldoem/base/sim_time.hpp>

#include <chrono>

namespace ldoem::motor::test {

inline double seconds(base::SimTime duration) { return std::chrono::duration<double>(duration).count(); }

}  // namespace ldoem::motor::test
