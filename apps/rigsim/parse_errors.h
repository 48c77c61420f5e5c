// What the option parser (CLI11) reports, in rigsim's words: which option is wrong and why, with
// "did you mean" for a misspelt command, option or choice. main() prints it and exits with 1, as
// docs/command-line.md documents for bad input (CLI11's own exit codes, 105, 109, 114, ..., are not rigsim's).
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace rigsim::cli {

// The message for `e`, raised while parsing `args` (argv without the program name) for `app`.
std::string DescribeParseError(const CLI::ParseError& e, const CLI::App& app, const std::vector<std::string>& args);

// The subcommand the parser was in when it failed (nullptr: none, the error is about the command).
const CLI::App* FailedSubcommand(const CLI::App& app);

// Option checks whose refusals read as sentences ("--max-features: must be more than 0 (got -3)"),
// in place of CLI::PositiveNumber and CLI::NonNegativeNumber.
CLI::Validator Positive();
CLI::Validator NonNegative();

// "A,B": two finite numbers and one comma between them, for options that take a pair
// (--intrinsics-sd F,P, --truth-sd ROT_DEG,POS_M); nullopt for anything else.
std::optional<std::array<double, 2>> NumberPair(const std::string& text);

}  // namespace rigsim::cli
