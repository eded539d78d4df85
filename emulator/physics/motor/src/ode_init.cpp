#include "ode_init.hpp"

#include <ode/ode.h>

#include <mutex>

namespace ldoem::motor {

void ensure_ode_initialised() {
  // dInitODE2 may not be called twice without dCloseODE (odeinit.h). A function-local once flag
  // is the process-wide state ODE itself imposes; it holds no simulation state.
  static std::once_flag initialised;
  std::call_once(initialised, [] { dInitODE2(0); });
  dAllocateODEDataForThread(dAllocateMaskAll);  // idempotent per thread
}

}  // namespace ldoem::motor
