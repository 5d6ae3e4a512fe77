#pragma once
// One exception type for bad input: it always names the file and, where known, the line and column,
// so every loader reports "file:line:col: what" and the CLI prints it without a stack trace.
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace sb {

class InputError : public std::runtime_error {
 public:
  InputError(std::string file, int line, int column, const std::string& what);
  InputError(std::string file, const std::string& what) : InputError(std::move(file), 0, 0, what) {}
  const std::string& file() const { return file_; }
  int line() const { return line_; }
  int column() const { return column_; }
  // The message without the "file:line:col: " prefix.
  const std::string& detail() const { return detail_; }

 private:
  std::string file_;
  int line_ = 0;
  int column_ = 0;
  std::string detail_;
};

// Text from a file quoted in an error message: bytes outside printable ASCII shown as \xNN, and cut after
// max_chars with "..." (a binary file's "header" must not reach the terminal raw).
std::string printable(std::string_view text, std::size_t max_chars = 80);

// Collects non-fatal problems (a non-unit quaternion, a mesh that is not a clean manifold) so the
// caller decides whether to print them; loaders never write to stderr themselves.
struct Warnings {
  std::vector<std::string> messages;
  void add(std::string m) { messages.push_back(std::move(m)); }
  bool empty() const { return messages.empty(); }
};

}  // namespace sb
