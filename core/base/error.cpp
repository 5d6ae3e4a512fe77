#include "core/base/error.hpp"

namespace sb {

static std::string format_location(const std::string& file, int line, int column, const std::string& what) {
  std::string s = file;
  if (line > 0) s += ":" + std::to_string(line);
  if (column > 0) s += ":" + std::to_string(column);
  return s + ": " + what;
}

InputError::InputError(std::string file, int line, int column, const std::string& what)
    : std::runtime_error(format_location(file, line, column, what)),
      file_(std::move(file)),
      line_(line),
      column_(column),
      detail_(what) {}

std::string printable(std::string_view text, std::size_t max_chars) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string out;
  for (const char ch : text) {
    if (out.size() >= max_chars) return out + "...";
    const auto c = static_cast<unsigned char>(ch);
    if (c >= 0x20 && c < 0x7f)
      out += ch;
    else
      out += {'\\', 'x', kHex[c >> 4], kHex[c & 15]};
  }
  return out;
}

}  // namespace sb
