// ldoem-scan's command line, parsed and checked by pure functions (design.md convention 1).
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ldoem/cloud/cloud_file.hpp"
#include "ldoem/cloud/cloud_render.hpp"
#include "ldoem/driver/endpoint.hpp"
#include "ldoem/driver/scanner.hpp"
#include "ldoem/hub/listen_address.hpp"
#include "ldoem/scan/acquisition.hpp"

namespace ldoem::scan {

inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;
inline constexpr int kExitUsage = 2;
inline constexpr int kExitSignalBase = 128;

enum class CloudEncoding : std::uint8_t { ascii, binary };

struct ScanOptions {
  bool help = false;
  bool help_all = false;  // --help-all: the full usage text; --help prints the brief one
  bool version = false;  // --version: print base::version_line and exit 0
  std::optional<driver::Endpoint> device;  // direct: --device
  std::optional<hub::ListenAddress> hub;   // through a hub: --hub with --hub-device
  std::string hub_device;
  std::optional<driver::Endpoint> lpt;
  double horizontal_apex_deg = 20.0;
  double horizontal_resolution_deg = 0.25;
  double vertical_apex_deg = 21.6;
  double vertical_resolution_deg = 0.18;
  std::uint16_t speed_hz = 10;
  bool half_step = false;
  double step_rate_hz = 200.0;
  std::string out_path;
  CloudEncoding encoding = CloudEncoding::binary;
  std::optional<std::string> preview_path;
  std::optional<std::string> render_path;
  std::string title;  // --title: first part of the render's title line  // perspective picture of the cloud (cloud_render.hpp)
  cloud::RenderColour render_colour = cloud::RenderColour::height;
  bool fit = false;
  std::chrono::milliseconds timeout{5000};
  std::uint32_t retries = kDefaultRetries;  // further attempts per step after a retryable fault
  // How a lost connection is reopened (--reconnect-*; libldoem's defaults); --device only.
  driver::ReconnectPolicy reconnect;
  bool reconnect_given = false;
  Vector3 optical_offset_m;
  std::optional<std::string> completion_script;  // --completion bash: print it and exit 0
};

// `args` without the program name (parsed with CLI11, base/command_line.hpp); the error is one
// line for stderr (exit code 2).
base::Expected<ScanOptions, std::string> parse_scan_options(const std::vector<std::string_view>& args);

// .ply or .pcd (case-insensitive) with the encoding; nullopt for any other extension.
std::optional<cloud::CloudFileFormat> output_format(std::string_view path, CloudEncoding encoding);

// The sector table and the layers the options ask for, or the one-line reason they are not
// possible (exit code 2).
base::Expected<AcquisitionPlan, std::string> make_plan(const ScanOptions& options);

std::string scan_usage(std::string_view program);
// What --help prints: a screen of scan_usage (base::brief_help).
std::string scan_brief_usage(std::string_view program);

}  // namespace ldoem::scan
