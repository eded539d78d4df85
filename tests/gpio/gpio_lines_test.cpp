// The gpio back end's edge reader (D8: lines DIR, CLK, MODE) against a gpio-sim chip, driven
// from "outside" through the simulator's pull attribute, as a drive board's inputs would be.
#include "ldoem/io/gpio_lines.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <vector>

#include "ldoem/io/event_loop.hpp"
#include "ldoem/test_support/gpio_sim_chip.hpp"

namespace ldoem::io {
namespace {

using namespace std::chrono_literals;

const std::vector<std::string> kLptLines{"DIR", "CLK", "MODE"};  // D8: DATA0, DATA1, DATA2
constexpr std::size_t kDir = 0;
constexpr std::size_t kClk = 1;

using test_support::pull_sim_line;
using test_support::sim_chip;
using test_support::SimChip;

class GpioLineReaderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string why_not;
    auto chip = sim_chip(why_not);
    ASSERT_TRUE(chip.has_value()) << why_not;
    chip_ = *chip;
    for (std::size_t offset = 0; offset < kLptLines.size(); ++offset) {
      ASSERT_TRUE(set_pull(offset, false));
    }
  }

  bool set_pull(std::size_t offset, bool up) {
    const bool pulled = pull_sim_line(chip_, static_cast<int>(offset), up);
    EXPECT_TRUE(pulled) << "pulling line " << offset << " of " << chip_.sysfs;
    return pulled;
  }

  GpioLineReader open_reader() {
    auto reader = GpioLineReader::open(chip_.label, kLptLines, "ldoem-test");
    EXPECT_TRUE(reader) << reader.error().message();
    if (!reader) {
      std::abort();  // every caller needs a reader; the failure above says why
    }
    return std::move(reader).value();
  }

  // Edges the reader reports within `limit`, through the EventLoop as the daemon would.
  std::vector<GpioEdgeEvent> collect(GpioLineReader& reader, std::size_t count,
                                     std::chrono::milliseconds limit) {
    std::vector<GpioEdgeEvent> all;
    auto loop = EventLoop::create();
    EXPECT_TRUE(loop);
    for (const int fd : reader.event_fds()) {
      EXPECT_TRUE((*loop)->watch(fd, Interest::readable, [&](Readiness) {
        auto events = reader.read_events();
        ASSERT_TRUE(events) << events.error().message();
        all.insert(all.end(), events->begin(), events->end());
        if (all.size() >= count) {
          (*loop)->stop();
        }
      }));
    }
    EXPECT_TRUE((*loop)->run_for(limit));
    return all;
  }

  SimChip chip_;
};

TEST_F(GpioLineReaderTest, OpenByLabel_RequestsTheThreeNamedLines) {
  GpioLineReader reader = open_reader();
  EXPECT_EQ(reader.line_names(), kLptLines);
  EXPECT_EQ(reader.chip_name().rfind("gpiochip", 0), 0u) << reader.chip_name();
  const auto fds = reader.event_fds();
  ASSERT_EQ(fds.size(), 3u);
  for (const int fd : fds) {
    EXPECT_GE(fd, 0);
  }
}

TEST_F(GpioLineReaderTest, OpenByChipName_FindsTheSameLines) {
  const std::string chip_name = chip_.sysfs.substr(chip_.sysfs.rfind('/') + 1);
  auto reader = GpioLineReader::open(chip_name, {"CLK"});
  ASSERT_TRUE(reader) << reader.error().message();
  EXPECT_EQ(reader->chip_name(), chip_name);
}

TEST_F(GpioLineReaderTest, ClockPulses_GiveAlternatingEdgesWithIncreasingKernelTimestamps) {
  GpioLineReader reader = open_reader();
  const auto before = EventLoop::now().time_since_epoch();
  // One edge at a time: the v1 uAPI finds an edge's direction by reading the level in its IRQ
  // thread, so edges closer together than that thread's latency merge (see docs/uml-harness.md).
  std::vector<GpioEdgeEvent> events;
  for (int transition = 0; transition < 6; ++transition) {
    ASSERT_TRUE(set_pull(kClk, transition % 2 == 0));
    const auto one = collect(reader, 1, 2s);
    events.insert(events.end(), one.begin(), one.end());
  }
  const auto after = EventLoop::now().time_since_epoch();

  ASSERT_EQ(events.size(), 6u);
  for (std::size_t i = 0; i < events.size(); ++i) {
    EXPECT_EQ(events[i].line_index, kClk);
    EXPECT_EQ(events[i].edge, i % 2 == 0 ? Edge::rising : Edge::falling) << "edge " << i;
    if (i > 0) {
      EXPECT_GT(events[i].timestamp, events[i - 1].timestamp) << "edge " << i;
    }
  }
  // The kernel stamps edges on CLOCK_MONOTONIC, the EventLoop's clock.
  EXPECT_GE(events.front().timestamp, before);
  EXPECT_LE(events.back().timestamp, after);
}

TEST_F(GpioLineReaderTest, DirectionSetBeforeClock_IsReportedBeforeIt) {
  GpioLineReader reader = open_reader();
  ASSERT_TRUE(set_pull(kDir, true));
  ASSERT_TRUE(set_pull(kClk, true));
  const auto events = collect(reader, 2, 5s);
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].line_index, kDir);
  EXPECT_EQ(events[0].edge, Edge::rising);
  EXPECT_EQ(events[1].line_index, kClk);
  EXPECT_EQ(events[1].edge, Edge::rising);
}

TEST_F(GpioLineReaderTest, Levels_FollowThePull) {
  GpioLineReader reader = open_reader();
  ASSERT_TRUE(set_pull(2, true));  // MODE: half step
  auto levels = reader.levels();
  ASSERT_TRUE(levels) << levels.error().message();
  EXPECT_EQ(*levels, (std::vector<int>{0, 0, 1}));
}

TEST_F(GpioLineReaderTest, NoEdges_ReadsNothing) {
  GpioLineReader reader = open_reader();
  auto events = reader.read_events();
  ASSERT_TRUE(events) << events.error().message();
  EXPECT_TRUE(events->empty());
}

TEST_F(GpioLineReaderTest, UnknownLineName_IsAnErrorNamingIt) {
  auto reader = GpioLineReader::open(chip_.label, {"DIR", "STROBE"});
  ASSERT_FALSE(reader);
  EXPECT_NE(reader.error().message().find("line STROBE"), std::string::npos)
      << reader.error().message();
}

TEST_F(GpioLineReaderTest, UnknownChipLabel_IsAnErrorNamingIt) {
  auto reader = GpioLineReader::open("no-such-chip", kLptLines);
  ASSERT_FALSE(reader);
  EXPECT_NE(reader.error().message().find("no-such-chip"), std::string::npos)
      << reader.error().message();
}

TEST_F(GpioLineReaderTest, LineAlreadyRequested_CannotBeRequestedTwice) {
  GpioLineReader first = open_reader();
  auto second = GpioLineReader::open(chip_.label, {"CLK"});
  ASSERT_FALSE(second);
  EXPECT_EQ(second.error().error_number, EBUSY) << second.error().message();
}

}  // namespace
}  // namespace ldoem::io
