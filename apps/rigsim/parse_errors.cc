#include "apps/rigsim/parse_errors.h"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "common/did_you_mean.h"

namespace rigsim::cli {
namespace {

bool StartsWith(const std::string& s, const std::string& prefix) { return s.rfind(prefix, 0) == 0; }

std::vector<std::string> CommandNames(const CLI::App& app) {
  std::vector<std::string> names;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) names.push_back(sub->get_name());
  return names;
}

std::string JoinNames(const std::vector<std::string>& names) {
  std::string list;
  for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
  return list;
}

// Every option name `cmd` takes, as typed: "--features", "-h".
std::vector<std::string> OptionNames(const CLI::App& cmd) {
  std::vector<std::string> names;
  for (const CLI::Option* opt : cmd.get_options()) {
    for (const std::string& n : opt->get_lnames()) names.push_back("--" + n);
    for (const std::string& n : opt->get_snames()) names.push_back("-" + n);
  }
  return names;
}

// CLI11 prints range limits with std::to_string ("0.100000"): the shortest form instead.
std::string Number(const std::string& text) {
  std::istringstream in(text);
  double v = 0;
  if (!(in >> v)) return text;
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%g", v);
  return buffer;
}

// "--opt: rest" -> {"--opt", "rest"}; {"", text} when there is no option in front.
std::pair<std::string, std::string> SplitOption(const std::string& text) {
  const size_t colon = text.find(": ");
  if (colon == std::string::npos || colon == 0 || text.find(' ') < colon) return {"", text};
  return {text.substr(0, colon), text.substr(colon + 2)};
}

// The part of a validator's message after the option, in words (CLI11's validators and checks).
std::string DescribeProblem(const std::string& problem) {
  const std::string kRange = "Value ", kIn = " not in range ", kTo = " to ";
  if (StartsWith(problem, kRange) && problem.find(kIn) != std::string::npos) {
    const size_t in = problem.find(kIn), to = problem.find(kTo, in + kIn.size());
    if (to != std::string::npos) {
      return problem.substr(kRange.size(), in - kRange.size()) + " is outside " +
             Number(problem.substr(in + kIn.size(), to - in - kIn.size())) + " to " + Number(problem.substr(to + kTo.size()));
    }
  }
  for (const auto& [prefix, words] : {std::pair<std::string, std::string>{"File does not exist: ", "no such file: "},
                                      {"Directory does not exist: ", "no such folder: "},
                                      {"Path does not exist: ", "no such file or folder: "}}) {
    if (StartsWith(problem, prefix)) return words + problem.substr(prefix.size());
  }
  // IsMember: "sifty not in {sift,rootsift,orb,akaze}"
  if (const size_t in = problem.find(" not in {"); in != std::string::npos && problem.back() == '}') {
    const std::string typed = problem.substr(0, in);
    std::vector<std::string> choices;
    std::istringstream list(problem.substr(in + 9, problem.size() - in - 10));
    for (std::string c; std::getline(list, c, ',');) choices.push_back(c);
    return "'" + typed + "' is not one of " + JoinNames(choices) + DidYouMean(typed, choices);
  }
  if (const size_t at = problem.find(" required "); at != std::string::npos && problem.size() > 8 &&
                                                    problem.compare(problem.size() - 8, 8, " missing") == 0) {
    return "needs a value";
  }
  if (StartsWith(problem, "At least ") && problem.find(" required but received ") != std::string::npos) {
    const size_t req = problem.find(" required but received ");
    return "takes " + problem.substr(9, req - 9) + " values, got " + problem.substr(req + 23);
  }
  return problem;
}

// The unknown arguments of an ExtrasError, in the order given (CLI11 lists them reversed).
std::vector<std::string> ExtraArguments(const std::string& what) {
  std::vector<std::string> extras;
  const size_t colon = what.find(": ");
  if (colon == std::string::npos) return extras;
  std::istringstream in(what.substr(colon + 2));
  for (std::string a; in >> a;) extras.insert(extras.begin(), a);
  return extras;
}

std::string DescribeExtras(const std::string& what, const CLI::App& cmd, bool in_subcommand) {
  const std::vector<std::string> extras = ExtraArguments(what);
  std::string message;
  for (const std::string& a : extras) {
    if (!StartsWith(a, "-")) continue;
    const std::string name = a.substr(0, a.find('='));
    message += (message.empty() ? "" : "; ") + std::string("unknown option ") + name + DidYouMean(name, OptionNames(cmd));
  }
  if (!message.empty()) return message;
  if (!in_subcommand && !extras.empty()) {
    return "unknown command '" + extras[0] + "'" + DidYouMean(extras[0], CommandNames(cmd)) + "; the commands are " +
           JoinNames(CommandNames(cmd));
  }
  std::string list;
  for (const std::string& a : extras) list += (list.empty() ? "'" : " '") + a + "'";
  return "unexpected argument" + std::string(extras.size() > 1 ? "s " : " ") + list;
}

}  // namespace

const CLI::App* FailedSubcommand(const CLI::App& app) {
  const std::vector<CLI::App*> parsed = app.get_subcommands();
  return parsed.empty() ? nullptr : parsed.back();
}

std::string DescribeParseError(const CLI::ParseError& e, const CLI::App& app, const std::vector<std::string>& args) {
  const CLI::App* sub = FailedSubcommand(app);
  const CLI::App& cmd = sub ? *sub : app;
  const std::string what = e.what();
  // Matched by their words: CLI11 gives some errors the app's name in place of their own.
  if (StartsWith(what, "The following argument")) return DescribeExtras(what, cmd, sub != nullptr);
  if (sub == nullptr && what == "A subcommand is required") {
    if (!args.empty() && !StartsWith(args[0], "-")) {
      return "unknown command '" + args[0] + "'" + DidYouMean(args[0], CommandNames(app)) + "; the commands are " +
             JoinNames(CommandNames(app));
    }
    if (!args.empty()) return "unknown option " + args[0] + DidYouMean(args[0], OptionNames(app)) + "; give a command first";
    return "give a command: " + JoinNames(CommandNames(app));
  }
  if (const size_t at = what.find(" excludes "); at != std::string::npos && StartsWith(what, "-")) {
    return what.substr(0, at) + " cannot be given with " + what.substr(at + 10);  // "--out excludes --rig-out"
  }
  if (const size_t at = what.find(" requires "); at != std::string::npos && StartsWith(what, "-")) {
    return what.substr(0, at) + " needs " + what.substr(at + 10) + " too";  // "--a requires --b"
  }
  const auto [option, problem] = SplitOption(what);
  return option.empty() ? DescribeProblem(problem) : option + ": " + DescribeProblem(problem);
}

namespace {

CLI::Validator NumberCheck(const std::string& description, bool (*ok)(double), const std::string& rule) {
  return CLI::Validator(
      [ok, rule](std::string& input) -> std::string {
        double v = 0;
        if (!CLI::detail::lexical_cast(input, v) || !std::isfinite(v) || !ok(v)) return "must be " + rule + " (got " + input + ")";
        return "";
      },
      description);
}

}  // namespace

CLI::Validator Positive() {
  return NumberCheck("> 0", [](double v) { return v > 0; }, "more than 0");
}

CLI::Validator NonNegative() {
  return NumberCheck(">= 0", [](double v) { return v >= 0; }, "0 or more");
}

std::optional<std::array<double, 2>> NumberPair(const std::string& text) {
  const size_t comma = text.find(',');
  if (comma == std::string::npos || text.find(',', comma + 1) != std::string::npos) return std::nullopt;
  std::array<double, 2> out{};
  const std::string parts[2] = {text.substr(0, comma), text.substr(comma + 1)};
  for (int i = 0; i < 2; ++i) {
    if (!CLI::detail::lexical_cast(parts[i], out[i]) || !std::isfinite(out[i])) return std::nullopt;
  }
  return out;
}

}  // namespace rigsim::cli
