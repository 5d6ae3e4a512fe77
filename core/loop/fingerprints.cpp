// The fingerprint registry (fingerprints.hpp).
#include "core/loop/fingerprints.hpp"

#include <string_view>

namespace sb {

namespace {

// The fingerprint registry: one entry per effect that has a fingerprint, keyed by the effect's catalogue id
// (tests/test_fingerprints.cpp checks every key against the effect catalogue, so a misspelt id fails there).
// needs_model: whether the check compares the measurement with the model's field on this sensor.
struct FingerprintEntry {
  std::string_view effect_id;
  bool (*needs_model)(const Sensor& sensor);
  FingerprintCheck (*check)(const Sensor& sensor, const std::vector<FingerprintSample>& calibration,
                            const std::vector<FingerprintSample>& validation, const FingerprintRules& rules);
};

constexpr FingerprintEntry kFingerprints[] = {
    {"viscoelastic_creep", [](const Sensor&) { return false; }, creep_check},
    {"lens_distortion", lens_needs_model, lens_check},
    {"subsurface_markers", [](const Sensor&) { return true; }, subsurface_check},
};

const FingerprintEntry* find_fingerprint(std::string_view effect_id) {
  for (const FingerprintEntry& e : kFingerprints)
    if (e.effect_id == effect_id) return &e;
  return nullptr;
}

}  // namespace

std::vector<std::string> fingerprinted_effects() {
  std::vector<std::string> ids;
  for (const FingerprintEntry& e : kFingerprints) ids.emplace_back(e.effect_id);
  return ids;
}

bool has_fingerprint(const std::string& effect_id) { return find_fingerprint(effect_id) != nullptr; }

bool fingerprint_needs_model(const std::string& effect_id, const Sensor& sensor) {
  const FingerprintEntry* e = find_fingerprint(effect_id);
  return e != nullptr && e->needs_model(sensor);
}

std::optional<FingerprintCheck> fingerprint_check(const std::string& effect_id, const Sensor& sensor,
                                                  const std::vector<FingerprintSample>& calibration,
                                                  const std::vector<FingerprintSample>& validation,
                                                  const FingerprintRules& rules) {
  const FingerprintEntry* e = find_fingerprint(effect_id);
  if (e == nullptr) return std::nullopt;
  return e->check(sensor, calibration, validation, rules);
}

}  // namespace sb
