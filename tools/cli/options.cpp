#include "tools/cli/options.h"

#include <fmt/core.h>

#include <charconv>
#include <utility>

#include "tools/cli/exit_codes.h"

namespace bitstep::cli {

std::optional<int> parse(CLI::App& app, const std::string& command, int argc, char** argv) {
  // App::parse's vector form takes the words without a program name, the
  // last one first (it pops them from the back).
  std::vector<std::string> words;
  for (int i = argc - 1; i >= 0; --i) words.emplace_back(argv[i]);
  try {
    app.parse(words);
  } catch (const CLI::CallForHelp&) {
    fmt::print("{}", app.help());
    return exit_code::success;
  } catch (const CLI::ParseError& error) {
    // CLI11 checks required arguments before it refuses unknown words:
    // name the unknown word, the likelier mistake ("run --no-such-option").
    const std::vector<std::string> unknown = app.remaining();
    const std::string what = unknown.empty() ? error.what() : CLI::ExtrasError(unknown).what();
    fmt::print(stderr, "bitstep {}: {}\n", command, what);
    return exit_code::usage;
  }
  return std::nullopt;
}

void refuse(const std::string& option, const std::string& needs, const std::string& text) {
  throw CLI::ValidationError(fmt::format("{} needs {}, got '{}'", option, needs, text));
}

CLI::Option* add_read(CLI::App& app, const std::string& name, const std::string& needs,
                      std::function<bool(const std::string&)> read, const std::string& description) {
  return app.add_option_function<std::string>(
      name,
      [name, needs, read = std::move(read)](const std::string& text) {
        if (!read(text)) refuse(name, needs, text);
      },
      description);
}

bool read_integer(const std::string& text, long long lo, long long hi, long long& out) {
  long long value = 0;
  const char* end = text.data() + text.size();
  const auto [stop, error] = std::from_chars(text.data(), end, value);
  if (text.empty() || text[0] == '-' || error != std::errc{} || stop != end || value < lo || value > hi) return false;
  out = value;
  return true;
}

}  // namespace bitstep::cli
