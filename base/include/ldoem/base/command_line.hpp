// How ldoem's tools (ldoem-emud, ldoem-hub, ldoem-scan, ldoem-conformance) read their command
// lines: CLI11 parses, and this wrapper keeps what the tools promise their users (design.md
// convention 1): each tool's own --help text, verbatim, with defaults and examples; every problem
// as one line "OPTION: reason", for stderr and exit code 2; a repeated option keeps its last
// value unless the tool takes them all. Values are checked by the tool's own functions, so the
// reasons stay the tool's.
#pragma once

#include <CLI/CLI.hpp>

#include <functional>
#include <initializer_list>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace ldoem::base {

// Whether -h/--help (and any flag added with answer_first) is read left to right like the rest
// (ldoem-emud: what comes before it must parse, what follows it is not read), or whether every
// problem on the line is reported first (the host tools).
enum class HelpPrecedence { after_problems, before_problems };

class CommandLine {
 public:
  explicit CommandLine(std::string program, HelpPrecedence precedence = HelpPrecedence::after_problems);

  // A flag like --version: with HelpPrecedence::before_problems it, too, wins over problems.
  void answer_first(const std::string& names, bool& given);

  // Where the tool declares its options (add_option, add_flag, take_text below).
  CLI::App& app() { return app_; }

  // Parses `args` (argv without the program name). Empty: parsed (see help_requested()); else
  // the one-line reason, e.g. "--speed: `3` is not a motor speed of 5..20 Hz (spec 6)".
  [[nodiscard]] std::optional<std::string> parse(std::span<const std::string_view> args);

  // -h or --help was given: the tool prints its brief usage (brief_help) and exits 0, whatever
  // else was given.
  bool help_requested() const { return help_; }

  // --help-all was given: the tool prints its full usage text (what help2man reads) and exits 0.
  bool help_all_requested() const { return help_all_; }

  // --version was given (every tool has it): the tool prints version_line(program) and exits 0.
  bool version_requested() const { return version_; }

  // `--completion bash` was given (hidden; it is no part of the usage text): the tool prints
  // completion_script() and exits 0.
  bool completion_requested() const { return !completion_shell_.empty(); }

  // A bash completion for the tool: its option names, and file names after any option.
  // Install with `source <(ldoem-hub --completion bash)`.
  std::string completion_script() const;

 private:
  CLI::App app_;
  std::string program_;
  HelpPrecedence precedence_;
  bool help_ = false;
  bool help_all_ = false;
  bool version_ = false;
  std::vector<std::pair<std::vector<std::string>, bool*>> first_answers_;
  std::string completion_shell_;
};

// What --help prints: a screen (at most 40 lines of at most 80 columns) taken from the tool's
// full text, so both say the same: its usage line, `purpose`, the lines of the named `options`
// (each with its continuation lines, in the order given), and a last line pointing to
// --help-all and the man page. Lines wider than 80 columns are wrapped. An option the full text
// does not describe is left out.
std::string brief_help(std::string_view program, std::string_view full_text, std::string_view purpose,
                       std::span<const std::string_view> options);
inline std::string brief_help(std::string_view program, std::string_view full_text, std::string_view purpose,
                              std::initializer_list<std::string_view> options) {
  return brief_help(program, full_text, purpose, std::span<const std::string_view>(options.begin(), options.size()));
}

// A bash completion for `program` from a CLI11 app: its long option names and its subcommands,
// and file names after an option that takes a value. CommandLine::completion_script uses it;
// ldoem-ctl, whose subcommands CommandLine does not model, calls it directly.
std::string completion_script(const CLI::App& app, std::string_view program);

// "ldoem-scan 0.9.0\n": what --version prints, the project's version (CMake's PROJECT_VERSION).
std::string version_line(std::string_view program);

// What every tool prints for a bad command line, one line for stderr (exit code 2):
// "ldoem-scan: --speed: `3` is not ... (try --help)\n". The hint is left out where the
// reason gives one already.
std::string usage_error_line(std::string_view program, std::string_view reason);

// Declares `--name VALUE` whose text goes to `accept`; accept returns nothing when the value is
// taken, else the reason (the message becomes "--name: reason", or the reason alone when it
// starts with the option's name: "--lpt pty:/x is the old spelling; ..."). Rejecting one value rejects
// the command line.
CLI::Option* take_text(CLI::App& app, const std::string& name,
                       std::function<std::optional<std::string>(const std::string&)> accept);

}  // namespace ldoem::base
