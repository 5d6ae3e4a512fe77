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
      file_(std::move(file)), line_(line), column_(column), detail_(what) {}

}  // namespace sb
