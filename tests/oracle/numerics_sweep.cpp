// The seeded random sweep of scripts/numerics-report: random byte strings through the same
// cases and judge as the differential fuzzer (fuzz_raycast_oracle.cpp), for a time budget or a
// number of cases, then the tallies as key=value lines (differential.hpp). Also writes the
// fuzzer's seed corpus from the hard scenes. --faults-file appends every fault's case to PATH
// (faults_file.hpp: one line per fault, at most 10,000 lines). --far-meshes keeps only scenes
// generated 1e6 m from the origin with at least one mesh (where the float arithmetic is weakest),
// by setting the case's "far" bit and skipping the cases without a mesh: every case still
// replays with --case, and --cases N with the seed of a timed run and its case count runs the
// same cases again (the skipped ones are not counted).
//   numerics_sweep [--seconds S] [--cases N] [--seed K] [--faults-file PATH] [--far-meshes]
//                  [--write-seeds DIR SCENE.yaml...]
#include "differential.hpp"
#include "faults_file.hpp"

#include "ldoem/scene/scene_loader.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <random>
#include <string>

namespace {

std::string hex(const std::vector<std::uint8_t>& bytes) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string out;
  for (const std::uint8_t b : bytes) out += {kDigits[b >> 4], kDigits[b & 15]};
  return out;
}

int write_seeds(const std::filesystem::path& dir, int argc, char** argv, int first) {
  std::filesystem::create_directories(dir);
  std::mt19937_64 random(1);
  for (int i = first; i < argc; ++i) {
    const auto scene = ldoem::scene::load_scene(argv[i]);
    if (!scene) {
      std::cerr << "numerics_sweep: " << argv[i] << ": " << scene.error().message() << "\n";
      return 1;
    }
    std::vector<std::uint8_t> rays(512);
    for (auto& b : rays) b = static_cast<std::uint8_t>(random());
    const auto bytes = ldoem::oracle::encode_scene(*scene, rays);
    std::ofstream(dir / std::filesystem::path(argv[i]).stem()).write(reinterpret_cast<const char*>(bytes.data()),
                                                                      static_cast<std::streamsize>(bytes.size()));
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  double seconds = 10.0;
  unsigned long long cases = 0, seed = 1;
  std::unique_ptr<ldoem::oracle::FaultsFile> faults_file;
  bool far_meshes = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--write-seeds" && i + 1 < argc) return write_seeds(argv[i + 1], argc, argv, i + 2);
    if (arg == "--far-meshes") {
      far_meshes = true;
      continue;
    }
    if (i + 1 >= argc) {
      std::cerr << "usage: numerics_sweep [--seconds S] [--cases N] [--seed K] [--faults-file PATH] [--far-meshes] [--write-seeds DIR SCENE...]\n";
      return 2;
    }
    if (arg == "--case") {  // one case, given as the hex of its bytes (as the report prints it)
      std::vector<std::uint8_t> bytes;
      const std::string h = argv[++i];
      for (std::size_t k = 0; k + 1 < h.size(); k += 2) bytes.push_back(static_cast<std::uint8_t>(std::stoi(h.substr(k, 2), nullptr, 16)));
      ldoem::oracle::Stats one;
      const auto c = ldoem::oracle::make_case(bytes);
      for (std::size_t k = 0; k < c.scene.objects.size(); ++k) {
        std::cout << "object " << k << " shape " << c.scene.objects[k].shape.index() << " at " << c.scene.objects[k].pose.position_m.transpose() << "\n";
      }
      ldoem::oracle::run_case(c, one, "given");
      if (faults_file) faults_file->add(one, h);
      std::cout << one.text();
      return one.fault_count() > 0 ? 1 : 0;
    }
    if (arg == "--seconds") seconds = std::stod(argv[++i]);
    else if (arg == "--cases") cases = std::stoull(argv[++i]);
    else if (arg == "--seed") seed = std::stoull(argv[++i]);
    else if (arg == "--faults-file") {
      faults_file = std::make_unique<ldoem::oracle::FaultsFile>(argv[++i]);
      if (!faults_file->ok()) {
        std::cerr << "numerics_sweep: cannot append to " << argv[i] << "\n";
        return 2;
      }
    } else {
      std::cerr << "numerics_sweep: unknown argument '" << arg << "'\n";
      return 2;
    }
  }
  std::mt19937_64 random(seed);
  ldoem::oracle::Stats stats;
  const auto start = std::chrono::steady_clock::now();
  for (unsigned long long n = 0; cases == 0 || n < cases;) {
    if (cases == 0 && std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > seconds) break;
    std::vector<std::uint8_t> bytes(64 + random() % 448);
    for (auto& b : bytes) b = static_cast<std::uint8_t>(random());
    bytes[0] &= 0xFE;  // generated scenes (the explicit form is for seeds)
    if (far_meshes) bytes[0] |= 2;  // the scene 1e6 m out (cases.cpp)
    const auto c = ldoem::oracle::make_case(bytes);
    if (far_meshes && std::none_of(c.scene.objects.begin(), c.scene.objects.end(), [](const ldoem::scene::SceneObject& o) {
          return std::holds_alternative<ldoem::scene::Mesh>(o.shape);
        })) {
      continue;
    }
    ++n;
    ldoem::oracle::Stats one;
    ldoem::oracle::run_case(c, one);
    if (one.fault_count() > 0 || one.oracle_failed > 0) {
      one = {};
      ldoem::oracle::run_case(ldoem::oracle::make_case(bytes), one, hex(bytes));
      if (faults_file) faults_file->add(one, hex(bytes));
    }
    // Worst cases are tagged with their bytes only when they become the worst (cheap).
    for (std::size_t k = 0; k < one.kinds.size(); ++k) {
      if (one.kinds[k].worst_ratio > stats.kinds[k].worst_ratio) one.kinds[k].worst_case += ", case " + hex(bytes);
    }
    stats.merge(one);
  }
  std::cout << "seed=" << seed << "\n" << stats.text();
  if (faults_file) std::cout << "faults_file_written=" << faults_file->written() << "\nfaults_file_dropped=" << faults_file->dropped() << "\n";
  return stats.fault_count() > 0 ? 1 : 0;
}
