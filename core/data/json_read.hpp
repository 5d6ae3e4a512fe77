#pragma once
// Reading JSON input files with errors that name the file and the JSON pointer of the bad entry
// ("scenes/x.json: /trajectory/keyframes/2/xyz_m: expected 3 numbers"); syntax errors name the file,
// line and column. Shared by the scene and tsd/1 readers.
#include <nlohmann/json.hpp>
#include <string>

#include "core/geometry/pose.hpp"

namespace sb::jsonin {

// Parses a whole file. Throws InputError(path) when it is missing, and InputError(path, line, col) on a
// syntax error.
nlohmann::json load_file(const std::string& path);

[[noreturn]] void fail(const std::string& file, const std::string& pointer, const std::string& what);

// Child pointer: "/a" + "b" -> "/a/b".
std::string child(const std::string& pointer, const std::string& key);
std::string child(const std::string& pointer, std::size_t index);

// The member `key` of object `obj`, or nullptr when absent.
const nlohmann::json* find(const nlohmann::json& obj, const char* key);
// Throws unless `obj` is an object whose keys are all in `allowed` (a typo should not pass silently).
void require_object(const nlohmann::json& obj, const std::string& file, const std::string& pointer);
void reject_unknown_keys(const nlohmann::json& obj, std::initializer_list<const char*> allowed, const std::string& file,
                         const std::string& pointer);

double finite_number(const nlohmann::json& j, const std::string& file, const std::string& pointer);
double positive_number(const nlohmann::json& j, const std::string& file, const std::string& pointer);
int integer(const nlohmann::json& j, const std::string& file, const std::string& pointer);
std::string string(const nlohmann::json& j, const std::string& file, const std::string& pointer);
bool boolean(const nlohmann::json& j, const std::string& file, const std::string& pointer);
Vec2 vec2(const nlohmann::json& j, const std::string& file, const std::string& pointer);
Vec3 vec3(const nlohmann::json& j, const std::string& file, const std::string& pointer);

// Required members: throw "<pointer>/<key>: missing" when absent.
const nlohmann::json& member(const nlohmann::json& obj, const char* key, const std::string& file,
                             const std::string& pointer);

}  // namespace sb::jsonin
