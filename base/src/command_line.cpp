#include "ldoem/base/command_line.hpp"

#include <algorithm>
#include <vector>

namespace ldoem::base {

CommandLine::CommandLine(std::string program, HelpPrecedence precedence)
    : app_("", program), program_(std::move(program)), precedence_(precedence) {
  app_.set_help_flag();  // the tool prints its own usage text instead of CLI11's
  answer_first("-h,--help", help_);
  answer_first("--help-all", help_all_);
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
    line += " (try --help)";
  }
  return line + "\n";
}

std::string CommandLine::completion_script() const { return base::completion_script(app_, program_); }

std::string completion_script(const CLI::App& app, std::string_view program_name) {
  const std::string program(program_name);
  std::string words;
  std::string value_options;  // after one of these, complete a file name
  const auto add_options = [&](const CLI::App& from) {
    for (const CLI::Option* option : from.get_options()) {
      for (const std::string& name : option->get_lnames()) {
        if (name == "completion" || words.find("--" + name + " ") != std::string::npos) continue;
        words += "--" + name + " ";
        if (option->get_type_size() != 0 && option->get_items_expected_max() != 0) value_options += (value_options.empty() ? "--" : "|--") + name;
      }
    }
  };
  add_options(app);
  for (const CLI::App* command : app.get_subcommands([](const CLI::App*) { return true; })) {
    words += command->get_name() + " ";
    add_options(*command);
  }
  if (!words.empty()) words.pop_back();
  if (value_options.empty()) value_options = "--completion";
  std::string function = "_" + program;
  for (char& c : function) {
    if (c == '-') c = '_';
  }
  return "# bash completion for " + program + "; load it with: source <(" + program + " --completion bash)\n" +
         function + "() {\n" +
         "  local current=${COMP_WORDS[COMP_CWORD]} previous=${COMP_WORDS[COMP_CWORD-1]}\n" +
         "  case $previous in\n" +
         "    " + value_options + ") COMPREPLY=($(compgen -f -- \"$current\")) ;;\n" +
         "    *) COMPREPLY=($(compgen -W \"" + words + "\" -- \"$current\")) ;;\n" +
         "  esac\n" +
         "}\n" +
         "complete -o filenames -F " + function + " " + program + "\n";
}

namespace {

constexpr std::size_t kColumns = 80;

std::size_t indentation(std::string_view line) {
  const std::size_t first = line.find_first_not_of(' ');
  return first == std::string_view::npos ? line.size() : first;
}

// Where a wrapped line goes on: under the description of an option line ("  --x N   text"),
// else under the usage line's first argument, else four columns in.
std::size_t continuation_column(std::string_view line) {
  const std::size_t text = indentation(line);
  const std::size_t gap = line.find("  ", text);
  if (gap != std::string_view::npos) {
    const std::size_t description = line.find_first_not_of(' ', gap);
    if (description != std::string_view::npos && description <= 40) return description;
  }
  const std::string_view words = line.substr(text);
  if (words.starts_with("usage:") || words.starts_with("Usage:")) {
    const std::size_t argument = line.find(' ', line.find(' ', text) + 1);
    if (argument != std::string_view::npos && argument < 40) return argument + 1;
  }
  return text + 4;
}

void append_wrapped(std::string& out, std::string_view line) {
  const std::string indent(continuation_column(line), ' ');
  std::string rest(line);
  while (rest.size() > kColumns) {
    std::size_t cut = rest.rfind(' ', kColumns);
    if (cut == std::string::npos || cut <= indentation(rest)) break;  // one word wider than the screen
    out += rest.substr(0, cut) + "\n";
    rest = indent + rest.substr(rest.find_first_not_of(' ', cut));
  }
  out += rest + "\n";
}

// The lines of `text`, without their line ends.
std::vector<std::string_view> lines_of(std::string_view text) {
  std::vector<std::string_view> lines;
  while (!text.empty()) {
    const std::size_t end = text.find('\n');
    lines.push_back(text.substr(0, end));
    text = end == std::string_view::npos ? std::string_view{} : text.substr(end + 1);
  }
  return lines;
}

// Whether `line` describes `option`: its first word, or one of its comma-separated spellings
// ("--verbose, -v", CLI11's "-h,--help"), is the option.
bool describes(std::string_view line, std::string_view option) {
  std::string_view words = line.substr(indentation(line));
  if (words.starts_with(option)) {
    const std::string_view after = words.substr(option.size());
    if (after.empty() || after.front() == ' ' || after.front() == ',' || after.front() == '=') return true;
  }
  for (std::size_t comma = words.find(','); comma != std::string_view::npos && comma < words.find("  ");
       comma = words.find(',', comma + 1)) {
    std::string_view next = words.substr(comma + 1);
    next.remove_prefix(std::min(next.find_first_not_of(' '), next.size()));
    if (next.starts_with(option) &&
        (next.size() == option.size() || next[option.size()] == ' ' || next[option.size()] == ',')) {
      return true;
    }
  }
  return false;
}

}  // namespace

std::string brief_help(std::string_view program, std::string_view full_text, std::string_view purpose,
                       std::span<const std::string_view> options) {
  const std::vector<std::string_view> lines = lines_of(full_text);
  std::string out;
  // The usage line: the first one saying "usage:" (CLI11 puts the description before it).
  std::string_view usage = lines.empty() ? std::string_view{} : lines.front();
  for (const std::string_view line : lines) {
    if (line.starts_with("usage:") || line.starts_with("Usage:")) {
      usage = line;
      break;
    }
  }
  append_wrapped(out, usage);
  append_wrapped(out, purpose);
  out += "\nMost used options:\n";
  for (const std::string_view option : options) {
    for (std::size_t i = 1; i < lines.size(); ++i) {
      const std::string_view line = lines[i];
      if (indentation(line) == 0 || !describes(line, option)) continue;
      // The option's description, its continuation lines (indented past the option column)
      // included, joined into one paragraph and wrapped again at 80 columns: the full text
      // is wrapped wider.
      const std::size_t column = continuation_column(line);
      std::string entry(line.substr(0, std::min(column, line.size())));
      std::string paragraph(column < line.size() ? line.substr(column) : std::string_view{});
      for (std::size_t j = i + 1; j < lines.size() && indentation(lines[j]) > indentation(line) + 1 &&
                                  indentation(lines[j]) < lines[j].size();
           ++j) {
        paragraph += " " + std::string(lines[j].substr(indentation(lines[j])));
      }
      const std::string indent(column, ' ');
      std::size_t start = 0;
      while (start < paragraph.size()) {
        std::size_t end = paragraph.size();
        if (entry.size() + end - start > kColumns) {
          const std::size_t room = kColumns > entry.size() ? kColumns - entry.size() : 0;
          const std::size_t cut = paragraph.rfind(' ', start + room);
          end = cut != std::string::npos && cut > start ? cut : paragraph.find(' ', start + room);
          if (end == std::string::npos) end = paragraph.size();
        }
        out += entry + paragraph.substr(start, end - start) + "\n";
        entry = indent;
        start = paragraph.find_first_not_of(' ', end);
        if (start == std::string::npos) start = paragraph.size();
      }
      if (paragraph.empty()) out += entry + "\n";
      break;
    }
  }
  const std::string name(program);
  out += "\nAll options: " + name + " --help-all; the manual: man " + name + "\n";
  return out;
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
