// ldoem-scan: parse, plan, open the device, acquire, write (docs/scan.md).
#include <iostream>

#include "ldoem/cloud/range_image.hpp"
#include "ldoem/driver/stop_signals.hpp"
#include "ldoem/hub/hub_client.hpp"
#include "ldoem/hub/scanner_device.hpp"
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
  hub::ScannerDeviceOptions device_options;
  device_options.scanner.request_timeout = options.timeout;
  device_options.scanner.reconnect = options.reconnect;
  device_options.stepper.step_rate_hz = options.step_rate_hz;
  return std::unique_ptr<driver::Device>(hub::ScannerDevice::from_endpoints(
      driver::format_endpoint(*options.device), *options.device, options.lpt, device_options));
}

int write_outputs(const scan::ScanOptions& options, const scan::Scan& result) {
  const auto format = scan::output_format(options.out_path, options.encoding);
  auto written = cloud::write_cloud_file(options.out_path, result.cloud, *format);
  if (!written) {
    std::cerr << "ldoem-scan: write " << options.out_path << ": " << cloud::to_string(written.error()) << "\n";
    return kExitFailure;
  }
  std::cerr << "ldoem-scan: " << result.cloud.size() << " points in " << result.layers_done << " layers written to "
            << options.out_path;
  if (result.retries_used > 0) {
    std::cerr << " (" << result.retries_used << " retries, " << result.restarts << " restarts after faults)";
  }
  std::cerr << "\n";
  if (options.preview_path) {
    auto preview = cloud::write_range_image_png(*options.preview_path, result.cloud);
    if (!preview) {
      std::cerr << "ldoem-scan: write " << *options.preview_path << ": " << cloud::to_string(preview.error()) << "\n";
      return kExitFailure;
    }
  }
  if (options.render_path) {
    cloud::RenderOptions render;
    render.colour = options.render_colour;
    auto written = cloud::write_render_png(*options.render_path, result.cloud, render);
    if (!written) {
      std::cerr << "ldoem-scan: write " << *options.render_path << ": " << cloud::to_string(written.error()) << "\n";
      return kExitFailure;
    }
  }
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
    std::cerr << "ldoem-scan: " << options.error() << "\n" << scan::scan_usage("ldoem-scan");
    return scan::kExitUsage;
  }
  if (options->help) {
    std::cout << scan::scan_usage("ldoem-scan");
    return scan::kExitOk;
  }
  if (options->completion_script) {
    std::cout << *options->completion_script;
    return scan::kExitOk;
  }
  auto plan = scan::make_plan(*options);
  if (!plan) {
    std::cerr << "ldoem-scan: " << plan.error() << "\n";
    return scan::kExitUsage;
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
  scan::ProgressBar progress = scan::ProgressBar::for_stderr();
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
