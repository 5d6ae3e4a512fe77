#pragma once
// Fingerprints: for an effect, the evidence that the base model's form error cannot fake, and the effect's
// main parameter estimated from that evidence alone (docs/effects.md, "Fingerprints").
//
// A whole-field fit of an effect over a model whose form is wrong by ~1 px uses the effect's parameters to
// patch that form (creep as a slow gain, subsurface attenuation as a gain). A fingerprint looks where the
// effect shows and a rate-independent contact model's error cannot:
//  - creep: the change of the measured field while the indenter is held still, and its change after
//    release. Every base model is rate-independent: it predicts no change in either, whatever its form;
//    the standard linear solid's (tau, c) are the ones that, undone, leave neither. Needs no model.
//  - lens distortion: the rest grid (core/loop/rest_grid_lens.hpp). The markers are printed on a lattice and
//    the lens images it bent about the principal point; no contact model touches the rest positions. When
//    the rest grid is not a lattice (the TacTip's dome), the part of the residual that is not symmetric about
//    the contact: a press or twist of an axisymmetric indenter gives a field symmetric about the contact
//    centre, and so does a contact model's error of it; the lens, fixed in the image, is not.
//  - subsurface markers: how much the measured field is low-passed on the marker grid against the model's
//    field (their fine-scale content, the energy of the grid Laplacian).
//
// Each fingerprint has its file pair (fingerprint_creep, fingerprint_lens, fingerprint_subsurface); this header
// is the registry that the loop asks.
#include <optional>
#include <string>
#include <vector>

#include "core/loop/fingerprint_creep.hpp"
#include "core/loop/fingerprint_lens.hpp"
#include "core/loop/fingerprint_subsurface.hpp"
#include "core/loop/fingerprint_support.hpp"

namespace sb {

// The effects that have a fingerprint (the registry's keys, catalogue ids), and whether it compares the
// measurement with the model's field (the lens does only when the sensor's rest grid is not a lattice).
std::vector<std::string> fingerprinted_effects();
bool has_fingerprint(const std::string& effect_id);
bool fingerprint_needs_model(const std::string& effect_id, const Sensor& sensor);

// The fingerprint of `effect_id` on each split and the finding (FingerprintCheck): creep holds tau_s and
// creep_fraction at the calibration estimate (evidence beyond model form). Lens, when the sensor's rest grid is
// a lattice: the rest grid is the evidence, the same on both splits; found when |k1| >= rules.min_k1 and
// >= rules.k1_sigmas standard errors, then k1 is held at it and k2 at 0 (evidence beyond model form, accepted on
// it: FingerprintCheck::Acceptance::kEvidence); not found whatever the residual says. Lens on a rest grid that is not a
// lattice: the residual's asymmetry; the whole-field fit of k1 must end within the agreement ratio of its estimate, k2
// held at 0 (a second radial term is not identified on a marker grid this coarse). Subsurface as that lens,
// with depth_m. nullopt for an effect without a fingerprint. The samples need pred_px when
// fingerprint_needs_model(effect_id, sensor).
std::optional<FingerprintCheck> fingerprint_check(const std::string& effect_id, const Sensor& sensor,
                                                  const std::vector<FingerprintSample>& calibration,
                                                  const std::vector<FingerprintSample>& validation,
                                                  const FingerprintRules& rules = {});

}  // namespace sb
