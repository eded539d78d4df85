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
  std::string path;         // "objects[3].motion.waypoints", for messages
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

  // Counts one node; returns the path it has (empty for a map key).
  std::string begin_node(const YAML::Mark& mark, bool* is_key) {
    *is_key = false;
    if (++nodes_ > kMaxSceneYamlNodes) {
      over(mark, stack_.empty() ? std::string() : stack_.back().path,
           "more than " + std::to_string(kMaxSceneYamlNodes) + " YAML nodes in the scene");
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
      return parent.path.empty() ? parent.key : parent.path + "." + parent.key;
    }
    const std::size_t index = parent.items++;
    if (parent.role == Role::objects && index >= kMaxSceneObjects) {
      over(mark, parent.path, "more than " + std::to_string(kMaxSceneObjects) + " objects");
    }
    if (parent.role == Role::waypoints && index >= kMaxWaypoints) {
      over(mark, parent.path, "needs 2 to " + std::to_string(kMaxWaypoints) + " waypoints");
    }
    return parent.path + "[" + std::to_string(index) + "]";
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
    frame.path = begin_node(mark, &is_key);
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
  while (parser.HandleNextDocument(counter)) {
  }
}

}  // namespace ldoem::scene::detail
