#include "yaml_precount.hpp"

#include "yaml_fields.hpp"

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/parser.h>

#include <istream>
#include <streambuf>
#include <vector>

namespace ldoem::scene::detail {
namespace {

// The text as an istream without a copy (YAML::Load(std::string) would copy it twice more).
class ViewBuffer : public std::streambuf {
 public:
  explicit ViewBuffer(std::string_view text) {
    char* begin = const_cast<char*>(text.data());  // read only: get area, no put area
    setg(begin, begin, begin + text.size());
  }
};

enum class Role : unsigned char { other, objects, waypoints };

struct Frame {
  bool map = false;
  bool next_is_key = true;  // maps: the next child starts a key
  std::string key;          // maps: the key of the value being read
  std::size_t items = 0;    // sequences: children so far
  Role role = Role::other;
  std::string label;        // its own part of the key path: "motion", "[3]" (joined only for a message)
};

class Counter final : public YAML::EventHandler {
 public:
  explicit Counter(const std::string& file) : file_(file) {}

  void OnDocumentStart(const YAML::Mark&) override {}
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark& mark, YAML::anchor_t) override { leaf(mark, {}); }
  void OnAlias(const YAML::Mark& mark, YAML::anchor_t) override { leaf(mark, {}); }
  void OnScalar(const YAML::Mark& mark, const std::string&, YAML::anchor_t, const std::string& value) override {
    leaf(mark, value);
  }
  void OnSequenceStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {
    open(mark, false);
  }
  void OnSequenceEnd() override { stack_.pop_back(); }
  void OnMapStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {
    open(mark, true);
  }
  void OnMapEnd() override { stack_.pop_back(); }

 private:
  [[noreturn]] void over(const YAML::Mark& mark, const std::string& path, std::string detail) const {
    SceneError error;
    error.kind = SceneErrorKind::out_of_range;
    error.file = file_;
    if (mark.line >= 0 && mark.column >= 0) {
      error.line = mark.line + 1;
      error.column = mark.column + 1;
    }
    error.key_path = path;
    error.detail = std::move(detail);
    throw LoadFailure{std::move(error)};
  }

  // "objects[3].motion.waypoints": the labels of the open containers, built only for a message.
  std::string path() const {
    std::string text;
    for (const Frame& frame : stack_) {
      if (!text.empty() && !frame.label.empty() && frame.label.front() != '[') text += '.';
      text += frame.label;
    }
    return text;
  }

  // Counts one node; returns its label in its parent (empty for a map key). Allocates nothing
  // per node but for keys longer than the short-string buffer: inputs of a few bytes can mean a
  // million nodes.
  std::string begin_node(const YAML::Mark& mark, bool* is_key) {
    *is_key = false;
    if (++nodes_ > kMaxSceneYamlNodes) {
      over(mark, path(), "more than " + std::to_string(kMaxSceneYamlNodes) + " YAML nodes in the scene");
    }
    if (stack_.empty()) return {};
    Frame& parent = stack_.back();
    if (parent.map) {
      if (parent.next_is_key) {
        parent.next_is_key = false;
        *is_key = true;
        return {};
      }
      parent.next_is_key = true;
      return parent.key;
    }
    const std::size_t index = parent.items++;
    if (parent.role == Role::objects && index >= kMaxSceneObjects) {
      over(mark, path(), "more than " + std::to_string(kMaxSceneObjects) + " objects");
    }
    if (parent.role == Role::waypoints && index >= kMaxWaypoints) {
      over(mark, path(), "needs 2 to " + std::to_string(kMaxWaypoints) + " waypoints");
    }
    return "[" + std::to_string(index) + "]";
  }

  void leaf(const YAML::Mark& mark, const std::string& value) {
    bool is_key = false;
    begin_node(mark, &is_key);
    if (is_key) stack_.back().key = value;
  }

  void open(const YAML::Mark& mark, bool map) {
    bool is_key = false;
    Frame frame;
    frame.map = map;
    frame.label = begin_node(mark, &is_key);
    if (!map && !is_key && !stack_.empty() && stack_.back().map) {
      const std::string& key = stack_.back().key;
      if (key == "objects" && stack_.size() == 1) frame.role = Role::objects;
      if (key == "waypoints") frame.role = Role::waypoints;
    }
    if (is_key) stack_.back().key.clear();  // a map or list as a key: refused later by MapReader
    stack_.push_back(std::move(frame));
  }

  const std::string& file_;
  std::vector<Frame> stack_;
  std::size_t nodes_ = 0;
};

}  // namespace

void precount_yaml(std::string_view text, const std::string& file) {
  ViewBuffer buffer(text);
  std::istream in(&buffer);
  YAML::Parser parser(in);
  Counter counter(file);
  // The first document only, as YAML::Load reads: on some malformed text yaml-cpp keeps starting
  // empty documents without consuming input (a 650-byte input made a million null nodes).
  parser.HandleNextDocument(counter);
}

}  // namespace ldoem::scene::detail
