#include "core/data/json_read.hpp"

#include <fstream>
#include <sstream>

#include "core/base/error.hpp"

namespace sb::jsonin {

namespace {

// Line and column (1-based) of byte offset `byte` (nlohmann reports the offset just past the bad token).
std::pair<int, int> line_column(const std::string& text, std::size_t byte) {
  int line = 1, col = 1;
  for (std::size_t i = 0; i + 1 < byte && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      col = 1;
    } else {
      ++col;
    }
  }
  return {line, col};
}

std::string type_name(const nlohmann::json& j) { return j.type_name(); }

}  // namespace

nlohmann::json load_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot open file (missing or unreadable)");
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = ss.str();
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    const auto [line, col] = line_column(text, e.byte);
    std::string what = e.what();
    // Keep nlohmann's explanation, drop its own "[json.exception.parse_error.101] parse error at ..." prefix.
    if (const auto p = what.find(": syntax error"); p != std::string::npos) what = what.substr(p + 2);
    throw InputError(path, line, col, "invalid JSON: " + what);
  } catch (const nlohmann::json::exception& e) {
    // Not a syntax error but still unreadable, e.g. out_of_range.406: a number too large for a double
    // (found by fuzz_params). nlohmann gives no position for these.
    std::string what = e.what();
    if (const auto p = what.find("] "); p != std::string::npos) what = what.substr(p + 2);
    throw InputError(path, "invalid JSON: " + what);
  }
}

void fail(const std::string& file, const std::string& pointer, const std::string& what) {
  throw InputError(file, (pointer.empty() ? std::string("/") : pointer) + ": " + what);
}

std::string child(const std::string& pointer, const std::string& key) { return pointer + "/" + key; }
std::string child(const std::string& pointer, std::size_t index) { return pointer + "/" + std::to_string(index); }

const nlohmann::json* find(const nlohmann::json& obj, const char* key) {
  if (!obj.is_object()) return nullptr;
  const auto it = obj.find(key);
  return it == obj.end() ? nullptr : &*it;
}

void require_object(const nlohmann::json& obj, const std::string& file, const std::string& pointer) {
  if (!obj.is_object()) fail(file, pointer, "expected an object, got " + type_name(obj));
}

void reject_unknown_keys(const nlohmann::json& obj, std::initializer_list<const char*> allowed, const std::string& file,
                         const std::string& pointer) {
  require_object(obj, file, pointer);
  for (const auto& [key, value] : obj.items()) {
    bool known = false;
    for (const char* a : allowed) known = known || key == a;
    if (!known) {
      std::string list;
      for (const char* a : allowed) list += std::string(list.empty() ? "" : ", ") + a;
      fail(file, child(pointer, key), "unknown key (expected one of: " + list + ")");
    }
  }
}

const nlohmann::json& member(const nlohmann::json& obj, const char* key, const std::string& file,
                             const std::string& pointer) {
  require_object(obj, file, pointer);
  const nlohmann::json* m = find(obj, key);
  if (!m) fail(file, child(pointer, key), "missing");
  return *m;
}

double finite_number(const nlohmann::json& j, const std::string& file, const std::string& pointer) {
  if (!j.is_number()) fail(file, pointer, "expected a number, got " + type_name(j));
  const double v = j.get<double>();
  if (!std::isfinite(v)) fail(file, pointer, "expected a finite number");
  return v;
}

double positive_number(const nlohmann::json& j, const std::string& file, const std::string& pointer) {
  const double v = finite_number(j, file, pointer);
  if (!(v > 0)) fail(file, pointer, "expected a positive number, got " + j.dump());
  return v;
}

int integer(const nlohmann::json& j, const std::string& file, const std::string& pointer) {
  if (!j.is_number_integer()) fail(file, pointer, "expected an integer, got " + j.dump());
  return j.get<int>();
}

std::string string(const nlohmann::json& j, const std::string& file, const std::string& pointer) {
  if (!j.is_string()) fail(file, pointer, "expected a string, got " + type_name(j));
  return j.get<std::string>();
}

bool boolean(const nlohmann::json& j, const std::string& file, const std::string& pointer) {
  if (!j.is_boolean()) fail(file, pointer, "expected true or false, got " + type_name(j));
  return j.get<bool>();
}

template <int N>
static Eigen::Matrix<double, N, 1> vecn(const nlohmann::json& j, const std::string& file, const std::string& pointer) {
  const std::string expected = "expected " + std::to_string(N) + " numbers";
  if (!j.is_array() || j.size() != N) fail(file, pointer, expected);
  Eigen::Matrix<double, N, 1> v;
  for (int i = 0; i < N; ++i) {
    if (!j[i].is_number() || !std::isfinite(j[i].get<double>())) fail(file, pointer, expected);
    v[i] = j[i].get<double>();
  }
  return v;
}

Vec2 vec2(const nlohmann::json& j, const std::string& file, const std::string& pointer) {
  return vecn<2>(j, file, pointer);
}
Vec3 vec3(const nlohmann::json& j, const std::string& file, const std::string& pointer) {
  return vecn<3>(j, file, pointer);
}

}  // namespace sb::jsonin
