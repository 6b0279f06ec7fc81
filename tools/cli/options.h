// Every bitstep command declares its options with CLI11 (Debian's
// libcli11-dev): CLI11 reads the command line, writes --help, and refuses an
// unknown option, a missing value or a missing argument. What is left here
// is what the commands share: one way to report a usage error (one line,
// "bitstep COMMAND: ...", exit status 2) and the readers of values whose
// refusal names the option, the accepted range and the text given.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <optional>
#include <string>

namespace bitstep::cli {

// Parses argv (the words after the command's name). nullopt: run the
// command; otherwise its exit status: 0 after --help printed the help, 2
// after a usage error printed "bitstep COMMAND: WHAT" to stderr.
std::optional<int> parse(CLI::App& app, const std::string& command, int argc, char** argv);

// Throws the usage error "OPTION needs NEEDS, got 'TEXT'" (from an option's
// reader, so that parse prints it as it is).
[[noreturn]] void refuse(const std::string& option, const std::string& needs, const std::string& text);

// An option with one value that `read` takes; a value it refuses (false)
// is refuse(name, needs, value).
CLI::Option* add_read(CLI::App& app, const std::string& name, const std::string& needs,
                      std::function<bool(const std::string&)> read, const std::string& description);

// An integer lo..hi, digits only (a sign, a blank or a trailing letter is
// refused, where strtol would take them).
bool read_integer(const std::string& text, long long lo, long long hi, long long& out);

// An option whose value is an integer lo..hi ("needs an integer lo..hi").
template <class T>
CLI::Option* add_integer(CLI::App& app, const std::string& name, long long lo, long long hi, T& out,
                         const std::string& description) {
  return add_read(
      app, name, "an integer " + std::to_string(lo) + ".." + std::to_string(hi),
      [lo, hi, &out](const std::string& text) {
        long long value = 0;
        if (!read_integer(text, lo, hi, value)) return false;
        out = static_cast<T>(value);
        return true;
      },
      description);
}

}  // namespace bitstep::cli
