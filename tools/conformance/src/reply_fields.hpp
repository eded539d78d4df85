// A telegram as named fields, for `--against`: the protocol codec decodes a reply
// (decode_response) and every field gets a stable name, so that a difference reads
// "status.sensor_mode: recorded 3, got 1" instead of a byte offset. Names:
//   service, status.sensor_mode, status.motor_mode, status.reserved, identification.text,
//   get_status.extra, <reply>.value (the one WORD of GET_SIGNAL, SET_SIGNAL, SET_CONFIG,
//   SET_TIME_*, GET_SYNC_CLOCK, SET_FILTER, SET_FUNCTION, DO_RESET replies; clock replies end in
//   .clock_ms), trans_measure.return_code, get_config.key, get_config.word[i],
//   get_function.sector/.function/.stop_ticks, failure.request, failure.reason,
//   profile.format/.sent/.count/.layer/.sectors, profile.sectorS.number/.step/.points/.tstart/
//   .startdir/.tend/.enddir, profile.sectorS.pointP.distance/.direction/.echo, profile.senstat.*.
// A payload the codec cannot decode is one field, `undecodable`, holding its hex.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "ldoem/protocol/bytes.hpp"

namespace ldoem::conformance {

struct NamedField {
  std::string name;
  std::string value;
  bool operator==(const NamedField&) const = default;
};

std::vector<NamedField> reply_fields(protocol::ByteView payload);

struct FieldDifference {
  std::string name;
  std::string recorded;  // "(absent)" when only the live reply has the field
  std::string live;      // "(absent)" when only the recording has it
};

// Fields that differ, in the recorded telegram's order (then fields only the live one has),
// leaving out every name that matches one of `masks` (fnmatch globs).
std::vector<FieldDifference> compare_fields(const std::vector<NamedField>& recorded, const std::vector<NamedField>& live,
                                            const std::vector<std::string>& masks);

}  // namespace ldoem::conformance
