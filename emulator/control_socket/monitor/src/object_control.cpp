// The monitor's D12 commands (move-object, add-object, remove-object): the control socket's side
// of the world. They act on the daemon (the shared world), not on one scanner.
// Each command runs on the loop's thread, between revolutions, so the casters are never busy;
// only add-object's parse, mesh import and the mesh's collision tree may be built on a worker
// thread (issue 27), and the result comes back to the loop's thread before it touches the world.
#include <poll.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <mutex>
#include <thread>

#include "ldoem/base/unique_fd.hpp"
#include "ldoem/control_socket/object_commands.hpp"
#include "ldoem/monitor/monitor.hpp"
#include "ldoem/plant/scene_plant.hpp"
#include "ldoem/raycast/ode_world.hpp"

namespace ldoem::monitor {

using control_socket::AddObjectRequest;
using control_socket::command_time;
using control_socket::CommandError;
using control_socket::MoveObjectRequest;
using control_socket::parse_add_object;
using control_socket::parse_move_object;
using control_socket::parse_remove_object;
using control_socket::RemoveObjectRequest;
using control_socket::CommandResult;
using nlohmann::json;

namespace {

// How long a stopping daemon waits for an import in flight (abandon_import).
constexpr std::chrono::milliseconds kImportGrace{5000};

double seconds(base::SimTime time) { return std::chrono::duration<double>(time).count(); }

CommandError refused(std::string desc) { return CommandError{std::string(control_socket::kGenericError), std::move(desc)}; }

json vector_json(const Eigen::Vector3d& v) { return json::array({v.x(), v.y(), v.z()}); }

// A world change that fails inside Embree or ODE (out of memory) is an error reply, never a
// dead daemon: the control socket answers every line. It runs on the loop's thread: the mesh
// trees it builds there are counted (query-status mesh_trees_built_on_loop), as each one kept
// the hosts waiting (0.1-0.5 s for large-rock.obj).
template <typename Change>
base::Expected<double, std::string> guarded(std::string_view command, std::uint64_t& trees_built, Change change) {
  const std::uint64_t before = raycast::TriMeshData::built_on_this_thread();
  base::Expected<double, std::string> outcome{0.0};
  try {
    outcome = change();
  } catch (const std::exception& failure) {
    outcome = base::Unexpected(std::string(command) + ": " + failure.what());
  }
  trees_built += raycast::TriMeshData::built_on_this_thread() - before;
  return outcome;
}

}  // namespace

CommandResult Monitor::move_object(const json& arguments) {
  auto parsed = parse_move_object(arguments);
  if (!parsed) return refused(parsed.error());
  const MoveObjectRequest& request = *parsed;
  const base::SimTime now = scheduler_.now();
  auto at_s = command_time(request.at_s, seconds(now));
  if (!at_s) return refused("move-object: " + at_s.error());
  if (world_ == nullptr) return refused("move-object: " + no_world_);
  auto moved = guarded("move-object", mesh_trees_on_loop_, [&] {
    return world_->move_object(request.name, request.pose, *at_s, request.keep_velocity);
  });
  if (!moved) return refused(moved.error());
  json data{{"name", request.name},
            {"position_m", vector_json(request.pose.position_m)},
            {"rpy_deg", vector_json(request.rpy_deg)},
            {"at_s", *moved},
            {"keep_velocity", request.keep_velocity}};
  publish_daemon({"OBJECT_MOVED", data, now});
  return json{{"name", request.name}, {"at_s", *moved}};
}

// The one add-object whose mesh is being imported. Shared with the worker, which may outlive the
// monitor (the daemon stops mid-import): it owns its eventfd, and it touches nothing else.
struct Monitor::Import {
  base::UniqueFd done;  // eventfd: written by the worker when `parsed` is set
  json arguments;
  ReplyLine reply_line;
  control_socket::ControlServer::Ticket ticket = 0;
  base::SimTime asked_at{};
  std::mutex mutex;
  control_socket::ParsedAddObject parsed{base::Unexpected(std::string("add-object: the import did not finish"))};
  std::shared_ptr<const raycast::TriMeshData> mesh;  // the imported mesh's trimesh data
};

CommandResult Monitor::add_object(const json& arguments) {
  const bool mesh = arguments.contains("object") && arguments["object"].is_object() && arguments["object"].contains("mesh");
  if (mesh && import_) return refused("add-object: another add-object is still importing its mesh; ask again when it has answered");
  return add_parsed(arguments, parse_add_object(arguments), scheduler_.now());
}

// Issue 27 (D8): the project's own large-rock.obj kept the loop, and so every host, unanswered
// for 657 ms while assimp read it. A mesh is now parsed and imported on a worker thread; the
// world changes on the loop's thread when it is done. One import at a time.
bool Monitor::add_object_later(const json& arguments, ReplyLine reply_line) {
  const bool mesh = arguments.contains("object") && arguments["object"].is_object() && arguments["object"].contains("mesh");
  if (!imports_off_loop_ || !mesh || import_ || server_ == nullptr || world_ == nullptr) return false;
  auto job = std::make_shared<Import>();
  job->done.reset(::eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK));
  if (!job->done.valid()) return false;  // no eventfd: import on the loop as before
  if (!loop_.watch(job->done.get(), io::Interest::readable, [this](io::Readiness) { finish_import(); })) return false;
  job->arguments = arguments;
  job->reply_line = std::move(reply_line);
  job->asked_at = scheduler_.now();
  job->ticket = server_->defer();
  import_ = job;
  std::thread([job] {
    auto parsed = parse_add_object(job->arguments);
    // The mesh's ODE tree (OPCODE) took the loop 0.2-0.5 s for large-rock.obj after the import
    // itself moved here: it is built here too, and the loop only makes the geom that uses it.
    std::shared_ptr<const raycast::TriMeshData> mesh;
    if (parsed) {
      if (const auto* shape = std::get_if<scene::Mesh>(&parsed->object.shape)) {
        try {
          mesh = raycast::TriMeshData::build(*shape);
        } catch (const std::exception& failure) {
          parsed = base::Unexpected(std::string("add-object: ") + failure.what());
        }
      }
    }
    {
      const std::lock_guard<std::mutex> lock(job->mutex);
      job->parsed = std::move(parsed);
      job->mesh = std::move(mesh);
    }
    const std::uint64_t one = 1;
    while (::write(job->done.get(), &one, sizeof one) < 0 && errno == EINTR) {
    }
  }).detach();
  return true;
}

void Monitor::finish_import() {
  const std::shared_ptr<Import> job = std::move(import_);
  if (!job) return;
  loop_.unwatch(job->done.get());
  control_socket::ParsedAddObject parsed{base::Unexpected(std::string())};
  std::shared_ptr<const raycast::TriMeshData> mesh;
  {
    const std::lock_guard<std::mutex> lock(job->mutex);
    parsed = std::move(job->parsed);
    mesh = std::move(job->mesh);
  }
  // The object goes in at the later of at_s and now: device time went on during the import (an
  // at_s already past when asked was refused as ever).
  if (parsed && parsed->at_s && *parsed->at_s >= seconds(job->asked_at) && *parsed->at_s < seconds(scheduler_.now())) {
    parsed->at_s.reset();
  }
  const CommandResult result = add_parsed(job->arguments, std::move(parsed), scheduler_.now(), std::move(mesh));
  if (server_) server_->complete(job->ticket, job->reply_line(result));
}

// The daemon stops during an import: the worker is given a bounded time to finish, so that it is
// not still inside assimp while the process runs its exit handlers; after that it is left alone
// (it owns everything it touches).
void Monitor::abandon_import() {
  if (!import_) return;
  loop_.unwatch(import_->done.get());
  pollfd done{import_->done.get(), POLLIN, 0};
  while (::poll(&done, 1, static_cast<int>(kImportGrace.count())) < 0 && errno == EINTR) {
  }
  import_.reset();
}

CommandResult Monitor::add_parsed(const json& arguments, control_socket::ParsedAddObject parsed,
                                      base::SimTime now, std::shared_ptr<const raycast::TriMeshData> mesh) {
  if (!parsed) return refused(parsed.error());
  AddObjectRequest& request = *parsed;
  auto at_s = command_time(request.at_s, seconds(now));
  if (!at_s) return refused("add-object: " + at_s.error());
  if (world_ == nullptr) return refused("add-object: " + no_world_);
  const std::string name = request.object.name;
  auto added = guarded("add-object", mesh_trees_on_loop_, [&] {
    return world_->add_object(std::move(request.object), *at_s, std::move(mesh));
  });
  if (!added) return refused(added.error());
  publish_daemon({"OBJECT_ADDED", json{{"name", name}, {"at_s", *added}, {"object", arguments["object"]}}, now});
  return json{{"name", name}, {"at_s", *added}};
}

CommandResult Monitor::remove_object(const json& arguments) {
  auto parsed = parse_remove_object(arguments);
  if (!parsed) return refused(parsed.error());
  const RemoveObjectRequest& request = *parsed;
  const base::SimTime now = scheduler_.now();
  auto at_s = command_time(request.at_s, seconds(now));
  if (!at_s) return refused("remove-object: " + at_s.error());
  if (world_ == nullptr) return refused("remove-object: " + no_world_);
  auto removed = guarded("remove-object", mesh_trees_on_loop_,
                         [&] { return world_->remove_object(request.name, *at_s); });
  if (!removed) return refused(removed.error());
  publish_daemon({"OBJECT_REMOVED", json{{"name", request.name}, {"at_s", *removed}}, now});
  return json{{"name", request.name}, {"at_s", *removed}};
}

}  // namespace ldoem::monitor
