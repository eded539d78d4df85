// ldoem-conformance: parse, load the vectors, list or run, map the outcome to an exit code.
#include <fstream>
#include <iostream>
#include <sstream>
#include <string_view>
#include <vector>

#include "ldoem/base/command_line.hpp"
#include "against.hpp"
#include "options.hpp"
#include "runner.hpp"
#include "vector_table.hpp"

int main(int argc, char** argv) {
  using namespace ldoem::conformance;
  const std::vector<std::string_view> arguments(argv + 1, argv + argc);
  auto options = parse_options(arguments);
  if (!options) {
    std::cerr << ldoem::base::usage_error_line("ldoem-conformance", options.error().message);
    return kExitUsageError;
  }
  if (options->version) {
    std::cout << ldoem::base::version_line("ldoem-conformance");
    return kExitAllPassed;
  }
  if (options->help_all) {
    std::cout << usage_text("ldoem-conformance");
    return 0;
  }
  if (options->help) {
    std::cout << brief_usage_text("ldoem-conformance");
    return kExitAllPassed;
  }
  if (options->completion_script) {
    std::cout << *options->completion_script;
    return kExitAllPassed;
  }
  if (options->against) {
    return run_against(*options, std::cout, std::cerr);
  }
  std::string yaml(embedded_vectors_yaml());
  if (options->vectors_file) {
    std::ifstream file(*options->vectors_file);
    if (!file) {
      std::cerr << "ldoem-conformance: open " << *options->vectors_file << ": cannot read\n";
      return kExitUsageError;
    }
    std::ostringstream text;
    text << file.rdbuf();
    yaml = text.str();
  }
  auto vectors = load_vector_table(yaml);
  if (!vectors) {
    std::cerr << "ldoem-conformance: " << vectors.error() << '\n';
    return kExitUsageError;
  }
  if (options->list) {
    list_cases(*options, *vectors, std::cout);
    return kExitAllPassed;
  }
  return run_cases(*options, *vectors, std::cout, std::cerr);
}
