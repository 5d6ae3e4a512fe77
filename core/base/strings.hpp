#pragma once
// Small string helpers shared across folders.
#include <string>
#include <vector>

namespace sb {

// The parts with `sep` between them ("a, b, c"); "" for none.
inline std::string join(const std::vector<std::string>& parts, const std::string& sep = ",") {
  std::string out;
  for (const auto& part : parts) out += (out.empty() ? "" : sep) + part;
  return out;
}

}  // namespace sb
