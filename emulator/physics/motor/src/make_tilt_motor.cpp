#include <ldoem/motor/dynamic_tilt_motor.hpp>
#include <ldoem/motor/ideal_tilt_motor.hpp>

namespace ldoem::motor {

std::unique_ptr<TiltMotor> make_tilt_motor(const scene::Scene& scene) {
  // D9: an effect the scene does not name costs nothing: no ODE world without motor_dynamics.
  if (scene.effects.has(scene::Effect::motor_dynamics)) {
    return std::make_unique<DynamicTiltMotor>(scene.scanner.tilt_motor);
  }
  return std::make_unique<IdealTiltMotor>(scene.scanner.tilt_motor);
}

}  // namespace ldoem::motor
