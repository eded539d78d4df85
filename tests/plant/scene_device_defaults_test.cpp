// The scene's word on the device (D3 texts, D4 flash defaults) in the control unit's types.
#include <gtest/gtest.h>

#include "ldoem/plant/scene_device_defaults.hpp"

namespace ldoem::plant {
namespace {

TEST(SceneDefaults, FlashDefaultsOfTheSceneModel_MatchFactoryConfig) {
  EXPECT_EQ(device_config_from(scene::FlashDefaults{}), control::factory_config());
  const control::IdentificationTexts texts = identification_from(scene::Identification{});
  EXPECT_EQ(texts, control::default_identification());
  EXPECT_EQ(texts.at(0x0001), "LD-OEM1000");
  EXPECT_EQ(texts.at(0x0011), "ldoem-emud");
}

TEST(SceneDefaults, TheScenesCanPair_ReachesTheFlash) {
  scene::FlashDefaults defaults;
  defaults.can_request_id = 0x700;
  defaults.can_response_id = 0x701;
  const control::DeviceConfig config = device_config_from(defaults);
  EXPECT_EQ(config.can.request_id, 0x700);
  EXPECT_EQ(config.can.response_id, 0x701);
}

}  // namespace
}  // namespace ldoem::plant
