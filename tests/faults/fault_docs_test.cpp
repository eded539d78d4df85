// docs/faults.md against the catalogue (fault_kind.hpp): a kind added to, renamed in or removed
// from the catalogue without its rows in the docs fails here, so the docs cannot drift from the
// one list of kinds.
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "ldoem/faults/fault_kind.hpp"

namespace ldoem::faults {
namespace {

struct DocsRow {
  std::vector<std::string> cells;
};

// The rows of the first table after the heading `## heading` (header and separator left out).
std::vector<DocsRow> faults_doc_table(const std::string& heading) {
  std::ifstream file(std::string(LDOEM_SOURCE_DIR) + "/docs/faults.md");
  EXPECT_TRUE(file) << "docs/faults.md not found";
  std::vector<DocsRow> rows;
  std::string line;
  bool in_section = false;
  int table_line = 0;
  while (std::getline(file, line)) {
    if (line.rfind("## ", 0) == 0) {
      if (in_section) break;
      in_section = line == "## " + heading;
      continue;
    }
    if (!in_section) continue;
    if (line.rfind('|', 0) != 0) {
      if (table_line > 0) break;
      continue;
    }
    if (table_line++ < 2) continue;  // the header and the |---| line
    DocsRow row;
    std::stringstream cells(line.substr(1));
    for (std::string cell; std::getline(cells, cell, '|');) row.cells.push_back(cell);
    rows.push_back(row);
  }
  EXPECT_FALSE(rows.empty()) << "no table under '## " << heading << "' in docs/faults.md";
  return rows;
}

// The `backticked` words of a cell.
std::vector<std::string> quoted_names(const std::string& cell) {
  static const std::regex quoted("`([a-z_]+)`");
  std::vector<std::string> names;
  for (auto it = std::sregex_iterator(cell.begin(), cell.end(), quoted); it != std::sregex_iterator(); ++it) {
    names.push_back((*it)[1]);
  }
  return names;
}

// Whether a cell names a transport: its lowercase name as a whole word ("CAN frames have their
// own CRC" is prose, not the transport column's `can`).
bool names_transport(const std::string& cell, Transport transport) {
  return std::regex_search(cell, std::regex("\\b" + std::string(protocol::transport_name(transport)) + "\\b"));
}

TEST(FaultDocs, KindsTableGivesEveryKindOnceWithItsClassAndTransports) {
  std::map<std::string, int> rows_per_kind;
  for (const DocsRow& row : faults_doc_table("Kinds")) {
    ASSERT_GE(row.cells.size(), 3U);
    const bool device = row.cells[1].find("device") != std::string::npos;
    for (const std::string& name : quoted_names(row.cells[0])) {
      ++rows_per_kind[name];
      const auto kind = fault_kind_from_name(name);
      ASSERT_TRUE(kind) << "docs/faults.md lists `" << name << "`, which the catalogue does not have";
      EXPECT_EQ(device, info(*kind).fault_class == FaultClass::device) << name << ": class column";
      for (Transport transport : {Transport::tcp, Transport::serial, Transport::can, Transport::lpt}) {
        EXPECT_EQ(names_transport(row.cells[2], transport), applies_to(*kind, transport))
            << name << ": transports column, " << protocol::transport_name(transport);
      }
    }
  }
  for (std::size_t i = 0; i < kFaultKindCount; ++i) {
    const std::string name(fault_name(static_cast<FaultKind>(i)));
    EXPECT_EQ(rows_per_kind[name], 1) << "`" << name << "` in docs/faults.md's Kinds table";
  }
}

TEST(FaultDocs, WhatIsProducedNamesEveryKind) {
  std::map<std::string, int> mentions;
  for (const DocsRow& row : faults_doc_table("What ldoem-emud produces today")) {
    for (const std::string& name : quoted_names(row.cells.at(0))) {
      EXPECT_TRUE(fault_kind_from_name(name)) << "docs/faults.md says `" << name << "` is produced: not in the catalogue";
      ++mentions[name];
    }
  }
  for (std::size_t i = 0; i < kFaultKindCount; ++i) {
    const std::string name(fault_name(static_cast<FaultKind>(i)));
    EXPECT_EQ(mentions[name], 1) << "`" << name << "` in docs/faults.md's 'What ldoem-emud produces today'";
  }
}

}  // namespace
}  // namespace ldoem::faults
