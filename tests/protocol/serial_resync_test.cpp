// The host side of the serial framing after D11 faults: a package cut short, a bad CRC and
// garbage between packages cost only the reply they hit, whatever the chunking (the STX of the
// next package restarts the scan, spec 4.2).
#include <vector>

#include "ldoem/protocol/serial_framing.hpp"
#include "test_support.hpp"

namespace ldoem::protocol {
namespace {

using test::concat;
using test::hex;
using test::kClockReply;
using test::kIdleReply;
using test::kStatusReply;
using test::telegrams_of;


// good, cut short (no CRC, no ETX), good, garbage, bad CRC, good.
Bytes faulty_serial_stream() {
  Bytes cut = encode_serial_reply(kIdleReply);
  cut.resize(cut.size() - 6);  // the CRC's last hex digits and ETX lost on the line
  Bytes bad_crc = encode_serial_reply(kClockReply);
  bad_crc[bad_crc.size() - 2] = bad_crc[bad_crc.size() - 2] == '0' ? '1' : '0';  // a CRC digit
  return concat({encode_serial_reply(kStatusReply), cut, encode_serial_reply(kIdleReply), hex("FF 13 37 41 42"),
                 bad_crc, encode_serial_reply(kClockReply)});
}

const std::vector<Bytes> kSerialSurvivors{kStatusReply, kIdleReply, kClockReply};

TEST(SerialResync, CutBadCrcAndGarbage_CostOnlyTheirOwnReply) {
  SerialReplyReassembler reassembler;
  EXPECT_EQ(telegrams_of(reassembler.feed(faulty_serial_stream())), kSerialSurvivors);
  EXPECT_EQ(reassembler.dropped_frames(), 2u);  // the cut package and the bad CRC
}

TEST(SerialResync, SplitAtEveryOffset_SameReplies) {
  const Bytes stream = faulty_serial_stream();
  for (std::size_t split = 0; split <= stream.size(); ++split) {
    SerialReplyReassembler reassembler;
    auto events = reassembler.feed(ByteView(stream.data(), split));
    auto rest = reassembler.feed(ByteView(stream.data() + split, stream.size() - split));
    events.insert(events.end(), rest.begin(), rest.end());
    EXPECT_EQ(telegrams_of(events), kSerialSurvivors) << "split at " << split;
  }
}

}  // namespace
}  // namespace ldoem::protocol
