#include "ldoem/base/command_line.hpp"

#include <algorithm>
#include <vector>

namespace ldoem::base {

CommandLine::CommandLine(std::string program, HelpPrecedence precedence)
    : app_("", program), program_(std::move(program)), precedence_(precedence) {
  app_.set_help_flag();  // the tool prints its own usage text instead of CLI11's
  answer_first("-h,--help", help_);
  answer_first("--version", version_);
  app_.add_option("--completion", completion_shell_)->check(CLI::IsMember({"bash"}))->group("");
  app_.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  app_.allow_extras();  // reported below as one line, like every other problem
}

void CommandLine::answer_first(const std::string& names, bool& given) {
  CLI::Option* flag = app_.add_flag(names, given)->disable_flag_override();
  std::vector<std::string> spellings;
  for (const std::string& name : flag->get_lnames()) spellings.push_back("--" + name);
  for (const std::string& name : flag->get_snames()) spellings.push_back("-" + name);
  first_answers_.emplace_back(std::move(spellings), &given);
}

namespace {

// CLI11 names a mismatch "--scene: 1 required TEXT missing" or "no-flash was given a disallowed
// flag override"; the tools say "--scene: needs a value" and "--no-flash: takes no value".
std::string describe_mismatch(const std::string& text) {
  if (text.find("flag override") != std::string::npos) {
    return "--" + text.substr(0, text.find(' ')) + ": takes no value";
  }
  return text.substr(0, text.find(':')) + ": needs a value";
}

}  // namespace

std::optional<std::string> CommandLine::parse(std::span<const std::string_view> args) {
  bool* answered = nullptr;
  if (precedence_ == HelpPrecedence::before_problems) {
    // Left to right: the first --help/--version ends the line; only what precedes it is read.
    for (std::size_t i = 0; i < args.size() && answered == nullptr; ++i) {
      for (auto& [spellings, given] : first_answers_) {
        if (std::find(spellings.begin(), spellings.end(), args[i]) != spellings.end()) {
          answered = given;
          args = args.first(i);
          break;
        }
      }
    }
  }
  // CLI11 takes the arguments last first.
  std::vector<std::string> reversed(args.rbegin(), args.rend());
  std::optional<std::string> problem;
  try {
    app_.parse(reversed);
    const std::vector<std::string> extras = app_.remaining();
    if (!extras.empty()) {
      const std::string& first = extras.front();
      problem = (first.starts_with("-") ? "unknown option `" : "unexpected argument `") + first + "` (try --help)";
    }
  } catch (const CLI::ArgumentMismatch& error) {
    problem = describe_mismatch(error.what());
  } catch (const CLI::ParseError& error) {
    problem = std::string(error.what());
  }
  if (!problem && answered != nullptr) {
    *answered = true;
  }
  return problem;
}

std::string version_line(std::string_view program) {
  return std::string(program) + " " + LDOEM_VERSION + "\n";
}

std::string usage_error_line(std::string_view program, std::string_view reason) {
  std::string line = std::string(program) + ": " + std::string(reason);
  // A reason that points at a document (docs/endpoints.md) has its hint already.
  if (reason.find("--help") == std::string_view::npos && reason.find("(docs/") == std::string_view::npos) {
    line += " (try " + std::string(program) + " --help)";
  }
  return line + "\n";
}

std::string CommandLine::completion_script() const {
  std::string words;
  std::string value_options;  // after one of these, complete a file name
  for (const CLI::Option* option : app_.get_options()) {
    for (const std::string& name : option->get_lnames()) {
      if (name == "completion") continue;
      words += (words.empty() ? "--" : " --") + name;
      if (option->get_type_size() != 0) value_options += (value_options.empty() ? "--" : "|--") + name;
    }
  }
  std::string function = "_" + program_;
  for (char& c : function) {
    if (c == '-') c = '_';
  }
  return "# bash completion for " + program_ + "; load it with: source <(" + program_ + " --completion bash)\n" +
         function + "() {\n" +
         "  local current=${COMP_WORDS[COMP_CWORD]} previous=${COMP_WORDS[COMP_CWORD-1]}\n" +
         "  case $previous in\n" +
         "    " + value_options + ") COMPREPLY=($(compgen -f -- \"$current\")) ;;\n" +
         "    *) COMPREPLY=($(compgen -W \"" + words + "\" -- \"$current\")) ;;\n" +
         "  esac\n" +
         "}\n" +
         "complete -o filenames -F " + function + " " + program_ + "\n";
}

CLI::Option* take_text(CLI::App& app, const std::string& name,
                       std::function<std::optional<std::string>(const std::string&)> accept) {
  return app.add_option_function<std::string>(name, [name, accept = std::move(accept)](const std::string& value) {
    if (auto problem = accept(value)) {
      // A reason that names the option already (an endpoint's old spelling) is taken whole.
      const bool named = problem->starts_with(name + " ") || problem->starts_with(name + ":");
      if (named) throw CLI::ValidationError(*problem);
      throw CLI::ValidationError(name, *problem);
    }
  });
}

}  // namespace ldoem::base
