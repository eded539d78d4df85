// Every service in every state (spec 5 with D2's entries; lead decisions 1-6), table-driven.
// Each row: the state the device is put in, one request, the reply it must send at once (text
// form of text.hpp; "" = no immediate reply) and the status byte afterwards.
#include <gtest/gtest.h>

#include "control_test_support.hpp"

namespace ldoem::control::test {
namespace {

enum class StartState { idle, spinning_up, rotate, measure, streaming };

std::string_view name_of(StartState start) {
  switch (start) {
    case StartState::idle: return "idle";
    case StartState::spinning_up: return "spinning_up";
    case StartState::rotate: return "rotate";
    case StartState::measure: return "measure";
    case StartState::streaming: return "streaming";
  }
  return "?";
}

// Puts the bench into `start` with a fixed history, so clock values are known:
// idle at t = 0; spinning_up at t = 1 s of a 2 s spin-up; rotate/measure/streaming at t = 2 s.
void enter(Bench& bench, StartState start) {
  switch (start) {
    case StartState::idle: return;
    case StartState::spinning_up:
      bench.request(kTcp1, "TRANS_ROTATE 0000");
      bench.advance_to(SimTime(1s));
      return;
    case StartState::rotate:
      bench.request(kTcp1, "TRANS_ROTATE 0000");
      bench.advance_to(SimTime(2s));
      return;
    case StartState::measure:
      bench.enter_measure();
      return;
    case StartState::streaming:
      bench.enter_measure();
      bench.request(kTcp1, "GET_PROFILE 0000 39ff");
      return;
  }
}

struct Row {
  StartState start;
  const char* request;
  const char* reply;
  std::uint8_t status_after;
};

void PrintTo(const Row& row, std::ostream* os) { *os << name_of(row.start) << ": " << row.request; }

class EveryServiceInEveryState : public ::testing::TestWithParam<Row> {};

TEST_P(EveryServiceInEveryState, RepliesAsDecided) {
  const Row& row = GetParam();
  Bench bench;
  enter(bench, row.start);
  const std::string before = bench.unit.dump(bench.now);
  EXPECT_EQ(bench.reply_text(kTcp1, row.request), row.reply) << "state before:\n" << before;
  EXPECT_EQ(bench.unit.status_byte().to_byte(), row.status_after) << bench.unit.dump(bench.now);
}

constexpr std::uint8_t kIdle = 0x01, kSpinning = 0x42, kRotate = 0x02, kMeasure = 0x03;

// "LD-OEM1000" in WORDs (D3 default sensor name).
#define NAME_WORDS "4c44 2d4f 454d 3130 3030"

const Row kRows[] = {
    // GET_IDENTIFICATION, GET_STATUS, GET_SIGNAL, SET_SIGNAL, GET_CONFIG, GET_FUNCTION,
    // GET_SYNC_CLOCK, DO_RESET: every state (D2).
    {StartState::idle, "GET_IDENTIFICATION 0001", "GET_IDENTIFICATION reply " NAME_WORDS, kIdle},
    {StartState::spinning_up, "GET_IDENTIFICATION 0001", "GET_IDENTIFICATION reply " NAME_WORDS, kSpinning},
    {StartState::rotate, "GET_IDENTIFICATION 0001", "GET_IDENTIFICATION reply " NAME_WORDS, kRotate},
    {StartState::measure, "GET_IDENTIFICATION 0001", "GET_IDENTIFICATION reply " NAME_WORDS, kMeasure},
    {StartState::streaming, "GET_IDENTIFICATION 0001", "GET_IDENTIFICATION reply " NAME_WORDS, kMeasure},
    {StartState::idle, "GET_STATUS", "GET_STATUS reply 0000 0001", kIdle},
    {StartState::spinning_up, "GET_STATUS", "GET_STATUS reply 0000 0042", kSpinning},
    {StartState::rotate, "GET_STATUS", "GET_STATUS reply 0000 0002", kRotate},
    {StartState::measure, "GET_STATUS", "GET_STATUS reply 0000 0003", kMeasure},
    {StartState::streaming, "GET_STATUS", "GET_STATUS reply 0000 0003", kMeasure},
    {StartState::idle, "GET_SIGNAL", "GET_SIGNAL reply 0000", kIdle},
    {StartState::spinning_up, "GET_SIGNAL", "GET_SIGNAL reply 0000", kSpinning},
    {StartState::rotate, "GET_SIGNAL", "GET_SIGNAL reply 0000", kRotate},
    {StartState::measure, "GET_SIGNAL", "GET_SIGNAL reply 0000", kMeasure},
    {StartState::streaming, "GET_SIGNAL", "GET_SIGNAL reply 0000", kMeasure},
    {StartState::idle, "SET_SIGNAL 0011", "SET_SIGNAL reply 0000", kIdle},
    {StartState::spinning_up, "SET_SIGNAL 0011", "SET_SIGNAL reply 0000", kSpinning},
    {StartState::rotate, "SET_SIGNAL 0011", "SET_SIGNAL reply 0000", kRotate},
    {StartState::measure, "SET_SIGNAL 0011", "SET_SIGNAL reply 0000", kMeasure},
    {StartState::streaming, "SET_SIGNAL 0011", "SET_SIGNAL reply 0000", kMeasure},
    {StartState::idle, "GET_CONFIG 0010", "GET_CONFIG reply 0010 0001 000a 0004", kIdle},
    {StartState::spinning_up, "GET_CONFIG 0010", "GET_CONFIG reply 0010 0001 000a 0004", kSpinning},
    {StartState::rotate, "GET_CONFIG 0010", "GET_CONFIG reply 0010 0001 000a 0004", kRotate},
    {StartState::measure, "GET_CONFIG 0010", "GET_CONFIG reply 0010 0001 000a 0004", kMeasure},
    {StartState::streaming, "GET_CONFIG 0010", "GET_CONFIG reply 0010 0001 000a 0004", kMeasure},
    {StartState::idle, "GET_FUNCTION 0000", "GET_FUNCTION reply 0000 0003 0870", kIdle},
    {StartState::spinning_up, "GET_FUNCTION 0001", "GET_FUNCTION reply 0001 0001 0e10", kSpinning},
    {StartState::rotate, "GET_FUNCTION 0002", "GET_FUNCTION reply 0002 0000 0000", kRotate},
    {StartState::measure, "GET_FUNCTION 0000", "GET_FUNCTION reply 0000 0003 0870", kMeasure},
    {StartState::streaming, "GET_FUNCTION 0007", "GET_FUNCTION reply 0007 0000 0000", kMeasure},
    {StartState::idle, "GET_SYNC_CLOCK", "GET_SYNC_CLOCK reply 0000", kIdle},
    {StartState::spinning_up, "GET_SYNC_CLOCK", "GET_SYNC_CLOCK reply 03e8", kSpinning},
    {StartState::rotate, "GET_SYNC_CLOCK", "GET_SYNC_CLOCK reply 07d0", kRotate},
    {StartState::measure, "GET_SYNC_CLOCK", "GET_SYNC_CLOCK reply 07d0", kMeasure},
    {StartState::streaming, "GET_SYNC_CLOCK", "GET_SYNC_CLOCK reply 07d0", kMeasure},
    {StartState::idle, "DO_RESET 0010", "DO_RESET reply 0010", kIdle},
    {StartState::spinning_up, "DO_RESET 0010", "DO_RESET reply 0010", kSpinning},
    {StartState::rotate, "DO_RESET 0010", "DO_RESET reply 0010", kRotate},
    {StartState::measure, "DO_RESET 0010", "DO_RESET reply 0010", kMeasure},
    {StartState::streaming, "DO_RESET 0010", "DO_RESET reply 0010", kMeasure},
    {StartState::idle, "DO_RESET 0002", "DO_RESET reply 0002", kIdle},
    {StartState::spinning_up, "DO_RESET 0002", "DO_RESET reply 0002", kIdle},
    {StartState::rotate, "DO_RESET 0002", "DO_RESET reply 0002", kIdle},
    {StartState::measure, "DO_RESET 0002", "DO_RESET reply 0002", kIdle},
    {StartState::streaming, "DO_RESET 0002", "DO_RESET reply 0002", kIdle},
    {StartState::idle, "DO_RESET 0000", "DO_RESET reply 0000", kIdle},
    {StartState::spinning_up, "DO_RESET 0001", "DO_RESET reply 0001", kIdle},
    {StartState::rotate, "DO_RESET 0000", "DO_RESET reply 0000", kIdle},
    {StartState::measure, "DO_RESET 0001", "DO_RESET reply 0001", kIdle},
    {StartState::streaming, "DO_RESET 0000", "DO_RESET reply 0000", kIdle},
    // SET_CONFIG only in IDLE, in-band 0x0001 elsewhere (D2).
    {StartState::idle, "SET_CONFIG 0010 0001 000a 0008", "SET_CONFIG reply 0000", kIdle},
    {StartState::spinning_up, "SET_CONFIG 0010 0001 000a 0008", "SET_CONFIG reply 0001", kSpinning},
    {StartState::rotate, "SET_CONFIG 0010 0001 000a 0008", "SET_CONFIG reply 0001", kRotate},
    {StartState::measure, "SET_CONFIG 0010 0001 000a 0008", "SET_CONFIG reply 0001", kMeasure},
    {StartState::streaming, "SET_CONFIG 0010 0001 000a 0008", "SET_CONFIG reply 0001", kMeasure},
    // SET_TIME_ABS / SET_TIME_REL / SET_FILTER outside MEASURE (D2 reason 3 in MEASURE).
    {StartState::idle, "SET_TIME_ABS 03e8", "SET_TIME_ABS reply 03e8", kIdle},
    {StartState::spinning_up, "SET_TIME_ABS 03e8", "SET_TIME_ABS reply 03e8", kSpinning},
    {StartState::rotate, "SET_TIME_ABS 03e8", "SET_TIME_ABS reply 03e8", kRotate},
    {StartState::measure, "SET_TIME_ABS 03e8", "SERVICE_FAILURE 0203 0003", kMeasure},
    {StartState::streaming, "SET_TIME_ABS 03e8", "SERVICE_FAILURE 0203 0003", kMeasure},
    {StartState::idle, "SET_TIME_REL fff6", "SET_TIME_REL reply fff6", kIdle},
    {StartState::spinning_up, "SET_TIME_REL fff6", "SET_TIME_REL reply 03de", kSpinning},
    {StartState::rotate, "SET_TIME_REL fff6", "SET_TIME_REL reply 07c6", kRotate},
    {StartState::measure, "SET_TIME_REL fff6", "SERVICE_FAILURE 0204 0003", kMeasure},
    {StartState::streaming, "SET_TIME_REL fff6", "SERVICE_FAILURE 0204 0003", kMeasure},
    {StartState::idle, "SET_FILTER 0001 0001", "SET_FILTER reply 0001", kIdle},
    {StartState::spinning_up, "SET_FILTER 0001 0000", "SET_FILTER reply 0001", kSpinning},
    {StartState::rotate, "SET_FILTER 0001 0001", "SET_FILTER reply 0001", kRotate},
    {StartState::measure, "SET_FILTER 0001 0001", "SERVICE_FAILURE 0209 0003", kMeasure},
    {StartState::streaming, "SET_FILTER 0001 0001", "SERVICE_FAILURE 0209 0003", kMeasure},
    // SET_FUNCTION outside MEASURE; FF FF in MEASURE (D2).
    {StartState::idle, "SET_FUNCTION 0002 0003 1000 0000", "SET_FUNCTION reply 0002", kIdle},
    {StartState::spinning_up, "SET_FUNCTION 0002 0003 1000 0000", "SET_FUNCTION reply 0002", kSpinning},
    {StartState::rotate, "SET_FUNCTION 0002 0003 1000 0001", "SET_FUNCTION reply 0002", kRotate},
    {StartState::measure, "SET_FUNCTION 0002 0003 1000 0000", "SET_FUNCTION reply ffff", kMeasure},
    {StartState::streaming, "SET_FUNCTION 0002 0003 1000 0000", "SET_FUNCTION reply ffff", kMeasure},
    // GET_PROFILE and CANCEL_PROFILE only in MEASURE (D2); GET_PROFILE's answer is the stream.
    {StartState::idle, "GET_PROFILE 0001 39ff", "SERVICE_FAILURE 0301 0003", kIdle},
    {StartState::spinning_up, "GET_PROFILE 0001 39ff", "SERVICE_FAILURE 0301 0003", kSpinning},
    {StartState::rotate, "GET_PROFILE 0001 39ff", "SERVICE_FAILURE 0301 0003", kRotate},
    {StartState::measure, "GET_PROFILE 0001 39ff", "", kMeasure},
    {StartState::streaming, "GET_PROFILE 0001 39ff", "", kMeasure},
    {StartState::idle, "CANCEL_PROFILE", "SERVICE_FAILURE 0302 0003", kIdle},
    {StartState::spinning_up, "CANCEL_PROFILE", "SERVICE_FAILURE 0302 0003", kSpinning},
    {StartState::rotate, "CANCEL_PROFILE 0000", "SERVICE_FAILURE 0302 0003", kRotate},
    {StartState::measure, "CANCEL_PROFILE", "CANCEL_PROFILE reply 0000 0003", kMeasure},
    {StartState::streaming, "CANCEL_PROFILE 0000", "CANCEL_PROFILE reply 0000 0003", kMeasure},
    // Transitions (spec 5, lead decision 4): every (state, target) pair.
    {StartState::idle, "TRANS_IDLE", "TRANS_IDLE reply 0000 0001", kIdle},
    {StartState::spinning_up, "TRANS_IDLE", "SERVICE_FAILURE 0402 0003", kSpinning},
    {StartState::rotate, "TRANS_IDLE", "TRANS_IDLE reply 0000 0001", kIdle},
    {StartState::measure, "TRANS_IDLE", "SERVICE_FAILURE 0402 0003", kMeasure},
    {StartState::streaming, "TRANS_IDLE 0000", "SERVICE_FAILURE 0402 0003", kMeasure},
    {StartState::idle, "TRANS_ROTATE 0000", "", kSpinning},
    {StartState::spinning_up, "TRANS_ROTATE 0000", "SERVICE_FAILURE 0403 0003", kSpinning},
    {StartState::rotate, "TRANS_ROTATE 0000", "TRANS_ROTATE reply 0000 0002", kRotate},
    {StartState::rotate, "TRANS_ROTATE 000a", "TRANS_ROTATE reply 0000 0002", kRotate},
    {StartState::rotate, "TRANS_ROTATE 0014", "", kSpinning},
    {StartState::rotate, "TRANS_ROTATE 0005", "", 0x92},  // slowing down: motor "too high" (spec 2.4)
    {StartState::measure, "TRANS_ROTATE 0000", "TRANS_ROTATE reply 0000 0002", kRotate},
    {StartState::streaming, "TRANS_ROTATE 000a", "TRANS_ROTATE reply 0000 0002", kRotate},
    {StartState::streaming, "TRANS_ROTATE 0014", "", kSpinning},
    {StartState::idle, "TRANS_MEASURE", "SERVICE_FAILURE 0404 0003", kIdle},
    {StartState::spinning_up, "TRANS_MEASURE", "SERVICE_FAILURE 0404 0003", kSpinning},
    {StartState::rotate, "TRANS_MEASURE 0000", "TRANS_MEASURE reply 0000 0003 0000", kMeasure},
    {StartState::measure, "TRANS_MEASURE", "TRANS_MEASURE reply 0000 0003 0000", kMeasure},
    {StartState::streaming, "TRANS_MEASURE", "TRANS_MEASURE reply 0000 0003 0000", kMeasure},
    // Unknown codes and unpublished layouts: reason 1 in every state (D2).
    {StartState::idle, "0500 0001", "SERVICE_FAILURE 0500 0001", kIdle},
    {StartState::spinning_up, "COM_ATTACH", "SERVICE_FAILURE 0601 0001", kSpinning},
    {StartState::rotate, "DIR", "SERVICE_FAILURE 0701 0001", kRotate},
    {StartState::measure, "MONITOR_RUN", "SERVICE_FAILURE 0801 0001", kMeasure},
    {StartState::streaming, "LD_REGISTER_APPLICATION", "SERVICE_FAILURE 0106 0001", kMeasure},
};

INSTANTIATE_TEST_SUITE_P(Table, EveryServiceInEveryState, ::testing::ValuesIn(kRows));

}  // namespace
}  // namespace ldoem::control::test
