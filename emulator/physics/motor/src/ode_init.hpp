// ODE must be initialised once per process before the first world is made (dInitODE2), and each
// thread that touches ODE needs its own data. This is the one place motor code does it.
#pragma once

namespace ldoem::motor {

void ensure_ode_initialised();

}  // namespace ldoem::motor
