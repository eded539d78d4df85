// The D13 rows of ldoem_bench_accuracy (docs/accuracy-vs-time.md): waveform against mixed_pixels
// at a depth step, snr_noise against noise, and the cylinder-edge profile the report plots.
#pragma once

#include <string>

namespace ldoem::bench {

//   BM_EchoAtEdge/<variant>  distance of each range from the nearest real surface at a depth step
//   BM_RangeNoise/<model>    range sigma and detection near the threshold, noise vs snr_noise
void register_echo_benchmarks();

// One profile across the corridor cylinder's edge with off, mixed_pixels and waveform, as
// "head_deg off_m mixed_pixels_m waveform_m" lines (0 = no echo). Returns a process exit code.
int write_edge_profile(const std::string& path);

}  // namespace ldoem::bench
