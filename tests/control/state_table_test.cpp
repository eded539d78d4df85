// Every service in every state (spec 5 with D2's entries; lead decisions 1-6), table-driven.
// Each row: the state the device is put in, one request, the reply it must send at once (text
// form of text.hpp; "" = no immediate reply) and the status byte afterwards.
#include <gtest/gtest.h>

#include "control_test_support.hpp"

namespace ldoem::control::test {
namespace {

enum class Start { idle, spinning_up, rotate, measure, streaming };

std::string_view name_of(Start start) {
  switch (start) {
    case Start::idle: return "idle";
    case Start::spinning_up: return "spinning_up";
    case Start::rotate: return "rotate";
    case Start::measure: return "measure";
    case Start::streaming: return "streaming";
  }
  return "?";
}

// Puts the bench into `start` with a fixed history, so clock values are known:
// idle at t = 0; spinning_up at t = 1 s of a 2 s spin-up; rotate/measure/streaming at t = 2 s.
void enter(Bench& bench, Start start) {
  switch (start) {
    case Start::idle: return;
    case Start::spinning_up:
      bench.request(kTcp1, "TRANS_ROTATE 0000");
      bench.advance_to(SimTime(1s));
      return;
    case Start::rotate:
      bench.request(kTcp1, "TRANS_ROTATE 0000");
      bench.advance_to(SimTime(2s));
      return;
    case Start::measure:
      bench.enter_measure();
      return;
    case Start::streaming:
      bench.enter_measure();
      bench.request(kTcp1, "GET_PROFILE 0000 39ff");
      return;
  }
}

struct Row {
  Start start;
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
    {Start::idle, "GET_IDENTIFICATION 0001", "GET_IDENTIFICATION reply " NAME_WORDS, kIdle},
    {Start::spinning_up, "GET_IDENTIFICATION 0001", "GET_IDENTIFICATION reply " NAME_WORDS, kSpinning},
    {Start::rotate, "GET_IDENTIFICATION 0001", "GET_IDENTIFICATION reply " NAME_WORDS, kRotate},
    {Start::measure, "GET_IDENTIFICATION 0001", "GET_IDENTIFICATION reply " NAME_WORDS, kMeasure},
    {Start::streaming, "GET_IDENTIFICATION 0001", "GET_IDENTIFICATION reply " NAME_WORDS, kMeasure},
    {Start::idle, "GET_STATUS", "GET_STATUS reply 0000 0001", kIdle},
    {Start::spinning_up, "GET_STATUS", "GET_STATUS reply 0000 0042", kSpinning},
    {Start::rotate, "GET_STATUS", "GET_STATUS reply 0000 0002", kRotate},
    {Start::measure, "GET_STATUS", "GET_STATUS reply 0000 0003", kMeasure},
    {Start::streaming, "GET_STATUS", "GET_STATUS reply 0000 0003", kMeasure},
    {Start::idle, "GET_SIGNAL", "GET_SIGNAL reply 0000", kIdle},
    {Start::spinning_up, "GET_SIGNAL", "GET_SIGNAL reply 0000", kSpinning},
    {Start::rotate, "GET_SIGNAL", "GET_SIGNAL reply 0000", kRotate},
    {Start::measure, "GET_SIGNAL", "GET_SIGNAL reply 0000", kMeasure},
    {Start::streaming, "GET_SIGNAL", "GET_SIGNAL reply 0000", kMeasure},
    {Start::idle, "SET_SIGNAL 0011", "SET_SIGNAL reply 0000", kIdle},
    {Start::spinning_up, "SET_SIGNAL 0011", "SET_SIGNAL reply 0000", kSpinning},
    {Start::rotate, "SET_SIGNAL 0011", "SET_SIGNAL reply 0000", kRotate},
    {Start::measure, "SET_SIGNAL 0011", "SET_SIGNAL reply 0000", kMeasure},
    {Start::streaming, "SET_SIGNAL 0011", "SET_SIGNAL reply 0000", kMeasure},
    {Start::idle, "GET_CONFIG 0010", "GET_CONFIG reply 0010 0001 000a 0004", kIdle},
    {Start::spinning_up, "GET_CONFIG 0010", "GET_CONFIG reply 0010 0001 000a 0004", kSpinning},
    {Start::rotate, "GET_CONFIG 0010", "GET_CONFIG reply 0010 0001 000a 0004", kRotate},
    {Start::measure, "GET_CONFIG 0010", "GET_CONFIG reply 0010 0001 000a 0004", kMeasure},
    {Start::streaming, "GET_CONFIG 0010", "GET_CONFIG reply 0010 0001 000a 0004", kMeasure},
    {Start::idle, "GET_FUNCTION 0000", "GET_FUNCTION reply 0000 0003 0870", kIdle},
    {Start::spinning_up, "GET_FUNCTION 0001", "GET_FUNCTION reply 0001 0001 0e10", kSpinning},
    {Start::rotate, "GET_FUNCTION 0002", "GET_FUNCTION reply 0002 0000 0000", kRotate},
    {Start::measure, "GET_FUNCTION 0000", "GET_FUNCTION reply 0000 0003 0870", kMeasure},
    {Start::streaming, "GET_FUNCTION 0007", "GET_FUNCTION reply 0007 0000 0000", kMeasure},
    {Start::idle, "GET_SYNC_CLOCK", "GET_SYNC_CLOCK reply 0000", kIdle},
    {Start::spinning_up, "GET_SYNC_CLOCK", "GET_SYNC_CLOCK reply 03e8", kSpinning},
    {Start::rotate, "GET_SYNC_CLOCK", "GET_SYNC_CLOCK reply 07d0", kRotate},
    {Start::measure, "GET_SYNC_CLOCK", "GET_SYNC_CLOCK reply 07d0", kMeasure},
    {Start::streaming, "GET_SYNC_CLOCK", "GET_SYNC_CLOCK reply 07d0", kMeasure},
    {Start::idle, "DO_RESET 0010", "DO_RESET reply 0010", kIdle},
    {Start::spinning_up, "DO_RESET 0010", "DO_RESET reply 0010", kSpinning},
    {Start::rotate, "DO_RESET 0010", "DO_RESET reply 0010", kRotate},
    {Start::measure, "DO_RESET 0010", "DO_RESET reply 0010", kMeasure},
    {Start::streaming, "DO_RESET 0010", "DO_RESET reply 0010", kMeasure},
    {Start::idle, "DO_RESET 0002", "DO_RESET reply 0002", kIdle},
    {Start::spinning_up, "DO_RESET 0002", "DO_RESET reply 0002", kIdle},
    {Start::rotate, "DO_RESET 0002", "DO_RESET reply 0002", kIdle},
    {Start::measure, "DO_RESET 0002", "DO_RESET reply 0002", kIdle},
    {Start::streaming, "DO_RESET 0002", "DO_RESET reply 0002", kIdle},
    {Start::idle, "DO_RESET 0000", "DO_RESET reply 0000", kIdle},
    {Start::spinning_up, "DO_RESET 0001", "DO_RESET reply 0001", kIdle},
    {Start::rotate, "DO_RESET 0000", "DO_RESET reply 0000", kIdle},
    {Start::measure, "DO_RESET 0001", "DO_RESET reply 0001", kIdle},
    {Start::streaming, "DO_RESET 0000", "DO_RESET reply 0000", kIdle},
    // SET_CONFIG only in IDLE, in-band 0x0001 elsewhere (D2).
    {Start::idle, "SET_CONFIG 0010 0001 000a 0008", "SET_CONFIG reply 0000", kIdle},
    {Start::spinning_up, "SET_CONFIG 0010 0001 000a 0008", "SET_CONFIG reply 0001", kSpinning},
    {Start::rotate, "SET_CONFIG 0010 0001 000a 0008", "SET_CONFIG reply 0001", kRotate},
    {Start::measure, "SET_CONFIG 0010 0001 000a 0008", "SET_CONFIG reply 0001", kMeasure},
    {Start::streaming, "SET_CONFIG 0010 0001 000a 0008", "SET_CONFIG reply 0001", kMeasure},
    // SET_TIME_ABS / SET_TIME_REL / SET_FILTER outside MEASURE (D2 reason 3 in MEASURE).
    {Start::idle, "SET_TIME_ABS 03e8", "SET_TIME_ABS reply 03e8", kIdle},
    {Start::spinning_up, "SET_TIME_ABS 03e8", "SET_TIME_ABS reply 03e8", kSpinning},
    {Start::rotate, "SET_TIME_ABS 03e8", "SET_TIME_ABS reply 03e8", kRotate},
    {Start::measure, "SET_TIME_ABS 03e8", "SERVICE_FAILURE 0203 0003", kMeasure},
    {Start::streaming, "SET_TIME_ABS 03e8", "SERVICE_FAILURE 0203 0003", kMeasure},
    {Start::idle, "SET_TIME_REL fff6", "SET_TIME_REL reply fff6", kIdle},
    {Start::spinning_up, "SET_TIME_REL fff6", "SET_TIME_REL reply 03de", kSpinning},
    {Start::rotate, "SET_TIME_REL fff6", "SET_TIME_REL reply 07c6", kRotate},
    {Start::measure, "SET_TIME_REL fff6", "SERVICE_FAILURE 0204 0003", kMeasure},
    {Start::streaming, "SET_TIME_REL fff6", "SERVICE_FAILURE 0204 0003", kMeasure},
    {Start::idle, "SET_FILTER 0001 0001", "SET_FILTER reply 0001", kIdle},
    {Start::spinning_up, "SET_FILTER 0001 0000", "SET_FILTER reply 0001", kSpinning},
    {Start::rotate, "SET_FILTER 0001 0001", "SET_FILTER reply 0001", kRotate},
    {Start::measure, "SET_FILTER 0001 0001", "SERVICE_FAILURE 0209 0003", kMeasure},
    {Start::streaming, "SET_FILTER 0001 0001", "SERVICE_FAILURE 0209 0003", kMeasure},
    // SET_FUNCTION outside MEASURE; FF FF in MEASURE (D2).
    {Start::idle, "SET_FUNCTION 0002 0003 1000 0000", "SET_FUNCTION reply 0002", kIdle},
    {Start::spinning_up, "SET_FUNCTION 0002 0003 1000 0000", "SET_FUNCTION reply 0002", kSpinning},
    {Start::rotate, "SET_FUNCTION 0002 0003 1000 0001", "SET_FUNCTION reply 0002", kRotate},
    {Start::measure, "SET_FUNCTION 0002 0003 1000 0000", "SET_FUNCTION reply ffff", kMeasure},
    {Start::streaming, "SET_FUNCTION 0002 0003 1000 0000", "SET_FUNCTION reply ffff", kMeasure},
    // GET_PROFILE and CANCEL_PROFILE only in MEASURE (D2); GET_PROFILE's answer is the stream.
    {Start::idle, "GET_PROFILE 0001 39ff", "SERVICE_FAILURE 0301 0003", kIdle},
    {Start::spinning_up, "GET_PROFILE 0001 39ff", "SERVICE_FAILURE 0301 0003", kSpinning},
    {Start::rotate, "GET_PROFILE 0001 39ff", "SERVICE_FAILURE 0301 0003", kRotate},
    {Start::measure, "GET_PROFILE 0001 39ff", "", kMeasure},
    {Start::streaming, "GET_PROFILE 0001 39ff", "", kMeasure},
    {Start::idle, "CANCEL_PROFILE", "SERVICE_FAILURE 0302 0003", kIdle},
    {Start::spinning_up, "CANCEL_PROFILE", "SERVICE_FAILURE 0302 0003", kSpinning},
    {Start::rotate, "CANCEL_PROFILE 0000", "SERVICE_FAILURE 0302 0003", kRotate},
    {Start::measure, "CANCEL_PROFILE", "CANCEL_PROFILE reply 0000 0003", kMeasure},
    {Start::streaming, "CANCEL_PROFILE 0000", "CANCEL_PROFILE reply 0000 0003", kMeasure},
    // Transitions (spec 5, lead decision 4): every (state, target) pair.
    {Start::idle, "TRANS_IDLE", "TRANS_IDLE reply 0000 0001", kIdle},
    {Start::spinning_up, "TRANS_IDLE", "SERVICE_FAILURE 0402 0003", kSpinning},
    {Start::rotate, "TRANS_IDLE", "TRANS_IDLE reply 0000 0001", kIdle},
    {Start::measure, "TRANS_IDLE", "SERVICE_FAILURE 0402 0003", kMeasure},
    {Start::streaming, "TRANS_IDLE 0000", "SERVICE_FAILURE 0402 0003", kMeasure},
    {Start::idle, "TRANS_ROTATE 0000", "", kSpinning},
    {Start::spinning_up, "TRANS_ROTATE 0000", "SERVICE_FAILURE 0403 0003", kSpinning},
    {Start::rotate, "TRANS_ROTATE 0000", "TRANS_ROTATE reply 0000 0002", kRotate},
    {Start::rotate, "TRANS_ROTATE 000a", "TRANS_ROTATE reply 0000 0002", kRotate},
    {Start::rotate, "TRANS_ROTATE 0014", "", kSpinning},
    {Start::rotate, "TRANS_ROTATE 0005", "", 0x92},  // slowing down: motor "too high" (spec 2.4)
    {Start::measure, "TRANS_ROTATE 0000", "TRANS_ROTATE reply 0000 0002", kRotate},
    {Start::streaming, "TRANS_ROTATE 000a", "TRANS_ROTATE reply 0000 0002", kRotate},
    {Start::streaming, "TRANS_ROTATE 0014", "", kSpinning},
    {Start::idle, "TRANS_MEASURE", "SERVICE_FAILURE 0404 0003", kIdle},
    {Start::spinning_up, "TRANS_MEASURE", "SERVICE_FAILURE 0404 0003", kSpinning},
    {Start::rotate, "TRANS_MEASURE 0000", "TRANS_MEASURE reply 0000 0003 0000", kMeasure},
    {Start::measure, "TRANS_MEASURE", "TRANS_MEASURE reply 0000 0003 0000", kMeasure},
    {Start::streaming, "TRANS_MEASURE", "TRANS_MEASURE reply 0000 0003 0000", kMeasure},
    // Unknown codes and unpublished layouts: reason 1 in every state (D2).
    {Start::idle, "0500 0001", "SERVICE_FAILURE 0500 0001", kIdle},
    {Start::spinning_up, "COM_ATTACH", "SERVICE_FAILURE 0601 0001", kSpinning},
    {Start::rotate, "DIR", "SERVICE_FAILURE 0701 0001", kRotate},
    {Start::measure, "MONITOR_RUN", "SERVICE_FAILURE 0801 0001", kMeasure},
    {Start::streaming, "LD_REGISTER_APPLICATION", "SERVICE_FAILURE 0106 0001", kMeasure},
};

INSTANTIATE_TEST_SUITE_P(Table, EveryServiceInEveryState, ::testing::ValuesIn(kRows));

}  // namespace
}  // namespace ldoem::control::test
