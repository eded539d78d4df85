// The D13 scene keys: waveform, snr_noise, atmosphere, echo_scale, retroreflective, the 250 m
// limit, and the effect combinations that would silently do nothing. Each bad value is a typed
// error with its place (file:line:column and key path).
#include "ldoem/scene/optics.hpp"
#include "ldoem/scene/scene_loader.hpp"

#include <gtest/gtest.h>

namespace ldoem::scene {
namespace {

TEST(D13Keys, EveryKey_Parses) {
  const auto result = load_scene_from_string(
      "effects: [waveform, snr_noise, atmosphere, intensity, incidence]\n"
      "scanner:\n"
      "  max_range_m: 250\n"
      "  optics: {echo_scale: log}\n"
      "  waveform: {pulse_width_s: 5e-9, threshold_factor: 2, detection: last}\n"
      "  snr_noise: {threshold_snr: 8}\n"
      "  atmosphere: {visibility_m: 200, fog_returns: false}\n"
      "objects: [{sphere: {radius_m: 1}, reflectance: 0.5, retroreflective: true}]\n",
      "d13.yaml");
  ASSERT_TRUE(result.has_value()) << result.error().message();
  const Scene& scene = result.value();
  EXPECT_TRUE(scene.effects.has(Effect::waveform));
  EXPECT_TRUE(scene.effects.has(Effect::snr_noise));
  EXPECT_TRUE(scene.effects.has(Effect::atmosphere));
  EXPECT_EQ(scene.scanner.max_range_m, 250.0);
  EXPECT_EQ(scene.scanner.optics.echo_scale, EchoScale::log);
  EXPECT_EQ(scene.scanner.waveform.pulse_width_s, 5e-9);
  EXPECT_EQ(scene.scanner.waveform.threshold_factor, 2.0);
  EXPECT_EQ(scene.scanner.waveform.detection, EchoDetection::last);
  EXPECT_EQ(scene.scanner.snr_noise.threshold_snr, 8.0);
  EXPECT_EQ(scene.scanner.atmosphere.visibility_m, 200.0);
  EXPECT_FALSE(scene.scanner.atmosphere.fog_returns);
  ASSERT_EQ(scene.objects.size(), 1u);
  EXPECT_TRUE(scene.objects[0].retroreflective);
  EXPECT_EQ(optical_reflectance(scene.objects[0]), 0.5 * kRetroReflectiveGain);
}

TEST(D13Keys, FogReturns_WithWaveformAndAtmosphere_Parse) {
  const auto result = load_scene_from_string(
      "effects: [waveform, atmosphere]\n"
      "scanner: {atmosphere: {visibility_m: 50, fog_returns: true, fog_overlap_m: 1.5}}\n",
      "fog.yaml");
  ASSERT_TRUE(result.has_value()) << result.error().message();
  EXPECT_TRUE(result.value().scanner.atmosphere.fog_returns);
  EXPECT_EQ(result.value().scanner.atmosphere.fog_overlap_m, 1.5);
}

TEST(D13Keys, Defaults_AreD6s) {
  const auto result = load_scene_from_string("{}", "d13.yaml");
  ASSERT_TRUE(result.has_value());
  const Scene& scene = result.value();
  EXPECT_EQ(scene.scanner.optics.echo_scale, EchoScale::linear);
  EXPECT_EQ(scene.scanner.waveform.detection, EchoDetection::first);
  EXPECT_EQ(scene.scanner.waveform.threshold_factor, 1.0);
}

struct BadKey {
  const char* title;
  const char* yaml;
  SceneErrorKind kind;
  const char* key_path;
  int line;
  int column;
};

const BadKey kBadKeys[] = {
    {"beyond the LD-OEM's 250 m", "scanner: {max_range_m: 251}", SceneErrorKind::out_of_range, "scanner.max_range_m", 1, 24},
    {"unknown detection", "scanner: {waveform: {detection: loudest}}", SceneErrorKind::out_of_range,
     "scanner.waveform.detection", 1, 33},
    {"pulse too short", "scanner: {waveform: {pulse_width_s: 1e-12}}", SceneErrorKind::out_of_range,
     "scanner.waveform.pulse_width_s", 1, 37},
    {"threshold below D6's", "scanner: {waveform: {threshold_factor: 0.5}}", SceneErrorKind::out_of_range,
     "scanner.waveform.threshold_factor", 1, 40},
    {"unknown waveform key", "scanner:\n  waveform: {width: 1}", SceneErrorKind::unknown_key, "scanner.waveform.width", 2, 14},
    {"zero visibility", "scanner: {atmosphere: {visibility_m: 0}}", SceneErrorKind::out_of_range,
     "scanner.atmosphere.visibility_m", 1, 38},
    {"fog_returns not a flag", "scanner: {atmosphere: {fog_returns: yes}}", SceneErrorKind::wrong_type,
     "scanner.atmosphere.fog_returns", 1, 37},
    {"fog returns without waveform", "effects: [intensity, atmosphere]\nscanner: {atmosphere: {fog_returns: true}}",
     SceneErrorKind::conflicting_keys, "scanner.atmosphere.fog_returns", 2, 37},
    {"fog overlap not positive", "scanner: {atmosphere: {fog_overlap_m: 0}}", SceneErrorKind::out_of_range,
     "scanner.atmosphere.fog_overlap_m", 1, 39},
    {"negative threshold SNR", "scanner: {snr_noise: {threshold_snr: -1}}", SceneErrorKind::out_of_range,
     "scanner.snr_noise.threshold_snr", 1, 38},
    {"unknown echo scale", "scanner: {optics: {echo_scale: loud}}", SceneErrorKind::out_of_range,
     "scanner.optics.echo_scale", 1, 32},
    {"retroreflective not a flag", "objects: [{sphere: {radius_m: 1}, retroreflective: 1}]", SceneErrorKind::wrong_type,
     "objects[0].retroreflective", 1, 52},
    {"incidence alone", "effects: [noise, incidence]", SceneErrorKind::conflicting_keys, "effects[1]", 1, 18},
    {"atmosphere alone", "effects: [atmosphere]", SceneErrorKind::conflicting_keys, "effects[0]", 1, 11},
    {"noise and snr_noise", "effects: [noise, intensity, snr_noise]", SceneErrorKind::conflicting_keys, "effects[2]", 1, 29},
};

void PrintTo(const BadKey& bad, std::ostream* out) { *out << bad.title; }

class BadD13Key : public ::testing::TestWithParam<BadKey> {};

TEST_P(BadD13Key, Load_GivesTypedErrorWithPlace) {
  const BadKey& bad = GetParam();
  const auto result = load_scene_from_string(bad.yaml, "scenes/x.yaml");
  ASSERT_FALSE(result.has_value()) << bad.title;
  const SceneError& error = result.error();
  EXPECT_EQ(error.kind, bad.kind) << bad.title << ": " << error.message();
  EXPECT_EQ(error.key_path, bad.key_path) << bad.title << ": " << error.message();
  EXPECT_EQ(error.line, bad.line) << bad.title << ": " << error.message();
  EXPECT_EQ(error.column, bad.column) << bad.title << ": " << error.message();
}

INSTANTIATE_TEST_SUITE_P(Table, BadD13Key, ::testing::ValuesIn(kBadKeys),
                         [](const ::testing::TestParamInfo<BadKey>& info) {
                           std::string name = info.param.title;
                           for (char& c : name) {
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           }
                           return name;
                         });

TEST(EchoScale, Log_IsStrictlyIncreasingAndDoesNotSaturateOverEightDecades) {
  OpticsConfig optics;
  optics.echo_scale = EchoScale::log;
  EXPECT_EQ(echo_value(optics, optics.min_irradiance), 1000);  // D6's value at the threshold
  std::uint16_t previous = 0;
  for (double ratio = 1.0; ratio <= 1e8; ratio *= 1.01) {
    const std::uint16_t echo = echo_value(optics, ratio * optics.min_irradiance);
    EXPECT_GE(echo, previous) << ratio;
    previous = echo;
  }
  EXPECT_LT(previous, 65535);
  EXPECT_EQ(echo_value(optics, 2e8 * optics.min_irradiance), 65535);
  // 171 times the threshold (the corridor's wall) no longer saturates: 1000 + 8000 log10(171).
  EXPECT_EQ(echo_value(optics, 171.0 * optics.min_irradiance), 18864);
  OpticsConfig linear;
  EXPECT_EQ(echo_value(linear, 171.0 * linear.min_irradiance), 65535);
}

TEST(RetroReflective, ReturnsGainTimesTheLambertianPower) {
  OpticsConfig optics;
  optics.calibration = calibration_for_max_range(optics, 63.1);
  const double lambertian = received_irradiance(optics, 0.5, 1.0, 10.0);
  EXPECT_NEAR(received_irradiance(optics, 0.5 * kRetroReflectiveGain, 1.0, 10.0), kRetroReflectiveGain * lambertian,
              1e-9 * kRetroReflectiveGain * lambertian);
}

}  // namespace
}  // namespace ldoem::scene
