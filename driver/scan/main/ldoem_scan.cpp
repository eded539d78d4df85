// ldoem-scan: parse, plan, open the device, acquire, write (docs/scan.md).
#include <cstdio>
#include <iostream>

#include "ldoem/base/command_line.hpp"
#include "ldoem/cloud/cloud_file.hpp"
#include "ldoem/cloud/cloud_render.hpp"
#include "ldoem/cloud/range_image.hpp"
#include "ldoem/driver/scanner_device.hpp"
#include "ldoem/driver/stop_signals.hpp"
#include "ldoem/hub/hub_client.hpp"
#include "ldoem/scan/output_files.hpp"
#include "ldoem/scan/progress_bar.hpp"
#include "ldoem/scan/scan_options.hpp"
#include "ldoem/scan/scene_fit.hpp"

namespace {

using namespace ldoem;
using scan::kExitFailure;

base::Expected<std::unique_ptr<driver::Device>, driver::DriverError> open_device(const scan::ScanOptions& options) {
  if (options.hub) {
    auto client = hub::HubClient::connect(*options.hub, options.timeout);
    if (!client) {
      return base::Unexpected<driver::DriverError>(client.error());
    }
    return std::unique_ptr<driver::Device>(std::make_unique<hub::HubDevice>(std::move(client.value()), options.hub_device));
  }
  driver::ScannerDeviceOptions device_options;
  device_options.scanner.request_timeout = options.timeout;
  device_options.scanner.reconnect = options.reconnect;
  device_options.stepper.step_rate_hz = options.step_rate_hz;
  return std::unique_ptr<driver::Device>(driver::ScannerDevice::from_endpoints(
      driver::format_endpoint(*options.device), *options.device, options.lpt, device_options));
}

// Every output file the options name, in the order they are written and reported.
std::vector<std::filesystem::path> output_paths(const scan::ScanOptions& options) {
  std::vector<std::filesystem::path> paths{options.out_path};
  if (options.preview_path) paths.emplace_back(*options.preview_path);
  if (options.render_path) paths.emplace_back(*options.render_path);
  return paths;
}

// The render's title line: what the user named it (the scene), the scanner, the settings.
std::string render_title(const scan::ScanOptions& options) {
  char settings[160];
  std::snprintf(settings, sizeof settings, "%.4g x %.4g deg at %.4g x %.4g deg, %u Hz", options.horizontal_apex_deg,
                options.vertical_apex_deg, options.horizontal_resolution_deg, options.vertical_resolution_deg,
                static_cast<unsigned>(options.speed_hz));
  std::string title = options.title.empty() ? std::string() : options.title + "  |  ";
  // The transport, not the whole endpoint: a TCP port is often ephemeral, and the same scan must
  // give the same picture.
  const std::string endpoint = options.device ? driver::format_endpoint(*options.device) : std::string();
  title += options.device ? "LD-OEM over " + endpoint.substr(0, endpoint.find(':'))
                          : "LD-OEM " + options.hub_device + " via hub";
  return title + "  |  " + settings;
}

// Encodes every output in memory first, so that a cloud that cannot be drawn writes nothing.
base::Expected<std::vector<scan::OutputFile>, std::string> encode_outputs(const scan::ScanOptions& options,
                                                                         const scan::Scan& result) {
  std::vector<scan::OutputFile> files;
  auto cloud_bytes = cloud::encode_cloud(result.cloud, *scan::output_format(options.out_path, options.encoding));
  if (!cloud_bytes) {
    return base::Unexpected(options.out_path + ": " + std::string(cloud::to_string(cloud_bytes.error())));
  }
  files.push_back({options.out_path, std::move(*cloud_bytes)});
  if (options.preview_path) {
    auto preview = cloud::encode_range_image_png(result.cloud);
    if (!preview) {
      return base::Unexpected(*options.preview_path + ": " + std::string(cloud::to_string(preview.error())));
    }
    files.push_back({*options.preview_path, std::move(*preview)});
  }
  if (options.render_path) {
    cloud::RenderOptions render;
    render.colour = options.render_colour;
    render.title = render_title(options);
    auto picture = cloud::encode_render_png(result.cloud, render);
    if (!picture) {
      return base::Unexpected(*options.render_path + ": " + std::string(cloud::to_string(picture.error())));
    }
    files.push_back({*options.render_path, std::move(*picture)});
  }
  return files;
}

int write_outputs(const scan::ScanOptions& options, const scan::Scan& result) {
  auto files = encode_outputs(options, result);
  if (!files) {
    std::cerr << "ldoem-scan: " << files.error() << " (no file written)\n";
    return kExitFailure;
  }
  if (auto written = scan::write_all_or_none(*files); !written) {
    std::cerr << "ldoem-scan: " << written.error() << " (no file written)\n";
    return kExitFailure;
  }
  std::cerr << "ldoem-scan: " << result.cloud.size() << " points in " << result.layers_done << " layers written to "
            << options.out_path;
  if (result.retries_used > 0) {
    std::cerr << " (" << result.retries_used << " retries, " << result.restarts << " restarts after faults)";
  }
  std::cerr << "\n";
  if (options.fit) {
    auto fit = scan::fit_scene(result.cloud);
    if (!fit) {
      std::cerr << "ldoem-scan: fit: " << fit.error() << "\n";
      return kExitFailure;
    }
    std::cout << scan::describe(*fit) << "\n";
  }
  return scan::kExitOk;
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string_view> args(argv + 1, argv + argc);
  auto options = scan::parse_scan_options(args);
  if (!options) {
    std::cerr << base::usage_error_line("ldoem-scan", options.error());
    return scan::kExitUsage;
  }
  if (options->version) {
    std::cout << base::version_line("ldoem-scan");
    return scan::kExitOk;
  }
  if (options->help_all) {
    std::cout << scan::scan_usage("ldoem-scan");
    return scan::kExitOk;
  }
  if (options->help) {
    std::cout << scan::scan_brief_usage("ldoem-scan");
    return scan::kExitOk;
  }
  if (options->completion_script) {
    std::cout << *options->completion_script;
    return scan::kExitOk;
  }
  auto plan = scan::make_plan(*options);
  if (!plan) {
    std::cerr << base::usage_error_line("ldoem-scan", plan.error());
    return scan::kExitUsage;
  }

  // Before the first request: a scan's time is not spent on an output that cannot be written.
  for (const auto& path : output_paths(*options)) {
    if (auto writable = scan::check_output_path(path); !writable) {
      std::cerr << "ldoem-scan: " << writable.error() << "\n";
      return kExitFailure;
    }
  }

  auto stop_signals = driver::StopSignals::block_and_open();
  if (!stop_signals) {
    std::cerr << "ldoem-scan: " << driver::describe(stop_signals.error()) << "\n";
    return kExitFailure;
  }

  auto device = open_device(*options);
  if (!device) {
    std::cerr << "ldoem-scan: " << driver::describe(device.error()) << "\n";
    return kExitFailure;
  }
  scan::ProgressBarOptions progress_options;
  progress_options.line_prefix = "ldoem-scan: ";
  scan::ProgressBar progress = scan::ProgressBar::for_stderr(progress_options);
  int signal_seen = 0;
  scan::AcquisitionHooks hooks;
  hooks.on_layer = [&progress](std::uint32_t done, std::uint32_t total) {
    progress.update(done, total, driver::Clock::now().time_since_epoch());
  };
  hooks.on_retry = [](const std::string& stage, const driver::DriverError& error, std::uint32_t attempt,
                      std::uint32_t retries) {
    std::cerr << "ldoem-scan: " << stage << ": " << driver::describe(error) << " (" << driver::describe(driver::recovery_for(error))
              << "); retry " << attempt << " of " << retries << "\n";
  };
  hooks.should_stop = [&signal_seen, &stop_signals] {
    if (signal_seen == 0) {
      signal_seen = stop_signals->take_pending();
    }
    return signal_seen != 0;
  };
  auto result = scan::acquire(**device, *plan, hooks);
  progress.finish();
  if (!result) {
    std::cerr << "ldoem-scan: " << scan::describe(result.error()) << "\n";
    return result.error().failure == scan::AcquisitionFailure::stopped ? scan::kExitSignalBase + signal_seen
                                                                        : kExitFailure;
  }
  return write_outputs(*options, *result);
}
