// The request side of the hub's loop: one parsed line becomes a reply from the hub itself, from
// the device's fresh data, or a job for the device's BEMH; the workers' replies come back here.
#include <algorithm>

#include "hub_impl.hpp"

namespace ldoem::hub {

using std::chrono::milliseconds;

void Hub::Impl::handle_line(std::uint64_t tag, const std::string& line) {
  if (line.find_first_not_of(" \t\r") == std::string::npos) {
    return;  // blank lines are ignored (handy with netcat)
  }
  counters.requests.fetch_add(1, std::memory_order_relaxed);
  auto request = parse_request(line);
  if (!request) {
    counters.errors.fetch_add(1, std::memory_order_relaxed);
    send_reply(tag, error_reply(request.error().id, request.error().kind, request.error().detail));
    return;
  }
  if (std::holds_alternative<DevicesCommand>(request->command)) {
    std::string list;
    for (const auto& handler : handlers) {
      list += (list.empty() ? "" : ",") + handler->device_name() + ":" + handler->handler_id();
    }
    send_reply(tag, ok_reply(request->id, "DEVICES", {{"devices", list}}));
    return;
  }
  const auto device = handler_by_device.find(request->device);
  if (device == handler_by_device.end()) {
    counters.errors.fetch_add(1, std::memory_order_relaxed);
    send_reply(tag, error_reply(request->id, "unknown_device", "no device named `" + request->device + "`"));
    return;
  }
  if (answer_from_cache(tag, *request, *device->second)) {
    counters.answered_from_cache.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  HubConnection& client = clients.at(tag);
  if (client.total_in_flight >= settings.max_in_flight) {
    counters.errors.fetch_add(1, std::memory_order_relaxed);
    send_reply(tag, error_reply(request->id, "busy",
                                "this client has " + std::to_string(client.total_in_flight) +
                                    " requests in flight already (at most " +
                                    std::to_string(settings.max_in_flight) + ")"));
    return;
  }
  if (!device->second->submit(BackendJob{client.frontend_id, client.alive, *request})) {
    counters.errors.fetch_add(1, std::memory_order_relaxed);
    send_reply(tag, error_reply(request->id, "busy",
                                request->device + " (" + device->second->handler_id() + "): request queue is full"));
    return;
  }
  counters.forwarded.fetch_add(1, std::memory_order_relaxed);
  ++client.in_flight[request->device];
  ++client.total_in_flight;
}

bool Hub::Impl::answer_from_cache(std::uint64_t tag, const HubRequest& request, const BackEndHandler& handler) {
  std::optional<milliseconds> asked;
  if (const auto* status = std::get_if<StatusCommand>(&request.command)) {
    asked = status->max_age;
  } else if (const auto* profile = std::get_if<ProfileCommand>(&request.command)) {
    asked = profile->max_age;
  } else {
    return false;
  }
  const milliseconds max_age = asked.value_or(settings.max_age);
  const HubConnection& client = clients.at(tag);
  const auto in_flight = client.in_flight.find(request.device);
  if (max_age.count() <= 0 || (in_flight != client.in_flight.end() && in_flight->second > 0)) {
    return false;
  }
  const auto now = Clock::now();
  std::vector<ReplyField> fields;
  Clock::time_point taken_at;
  if (std::holds_alternative<StatusCommand>(request.command)) {
    const auto cached = handler.latest_status();
    if (!cached) {
      return false;
    }
    fields = status_fields(cached->status);
    taken_at = cached->taken_at;
  } else {
    const auto cached = handler.latest_profile();
    if (!cached) {
      return false;
    }
    fields = profile_fields(cached->sample);
    taken_at = cached->taken_at;
  }
  const auto age = std::chrono::duration_cast<milliseconds>(now - taken_at);
  if (age > max_age) {
    return false;
  }
  fields.emplace_back("handler", handler.handler_id());
  fields.emplace_back("source", "cache");
  fields.emplace_back("age_ms", std::to_string(age.count()));
  send_reply(tag, ok_reply(request.id, std::string(command_name(request.command)), std::move(fields)));
  return true;
}

void Hub::Impl::deliver_completions() {
  std::deque<BackendResult> ready;
  {
    std::lock_guard lock(completions_mutex);
    ready.swap(completions);
  }
  for (BackendResult& result : ready) {
    if (result.notice) {
      // A device's health is news for every client, not only the asker. send_reply may drop a
      // slow client, so the tags are taken first.
      std::vector<std::uint64_t> everyone;
      everyone.reserve(clients.size());
      for (const auto& entry : clients) {
        everyone.push_back(entry.first);
      }
      for (const std::uint64_t client_tag : everyone) {
        send_reply(client_tag, *result.notice);
      }
    }
    const auto tag = tag_by_frontend.find(result.frontend_id);
    if (tag == tag_by_frontend.end()) {
      continue;  // the client left; its reply has nobody to go to
    }
    HubConnection& client = clients.at(tag->second);
    if (auto in_flight = client.in_flight.find(result.device);
        in_flight != client.in_flight.end() && in_flight->second > 0) {
      --in_flight->second;
      --client.total_in_flight;
    }
    client.last_activity = Clock::now();
    if (!result.reply.ok) {
      counters.errors.fetch_add(1, std::memory_order_relaxed);
    }
    send_reply(tag->second, result.reply);
  }
}

}  // namespace ldoem::hub
