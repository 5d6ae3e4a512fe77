#pragma once
// Lattice-slip detector for a tracked pin field (pin_tracker.hpp).
//
// A wrong correspondence on a hexagonal pin lattice is rarely random: a pin, or a whole region, takes the
// detection one or more lattice sites away. The check tests what a correct correspondence must preserve:
// - topology: two rest neighbours are matched to image pins with no other detected pin between them (no
//   detection inside the circle on their segment, shrunk by `gabriel_margin`: a skipped site sits near
//   the segment's middle, while a real lattice edge only gets a detection that close under a compression
//   of the cell by more than half). A slip, abrupt or spread over several rings, must skip a site
//   somewhere, because a map between lattice patches that keeps every cell a cell is a lattice
//   translation of the whole patch;
// - no crossing: every rest triangle keeps its orientation;
// - continuity: first-ring pairs differ in displacement by at most `max_relative_step` of their distance
//   (a slip by one site gives >= ~1);
// - the whole-patch translation the topology cannot see: a translation by one site moves the whole
//   correspondence one lattice step, so the pins on the leading rim would need detections beyond it and
//   those on the trailing rim's detections would be left over. registration_margin counts how many more
//   pins the found registration explains than the best one-site translation of it could (at most: the
//   pins whose neighbour in that direction is matched, plus every unmatched detection), counted on the
//   pins the local tests leave (a field whose slipped part is the larger one keeps that part); <= 0 means
//   the image cannot tell them apart and every tracked pin is suspect. With a prior from the sample's known
//   inputs (pin_field_prior.hpp), the component-wise median of (tracked - prior) must also stay under
//   `max_coherent_prior_miss` pitches. Pins farther than `max_prior_miss` from the prior are counted (a
//   diagnostic of the prior), not flagged: the prior is a regression; the lattice decides.
// Last, tracked pins cut off from the largest group of unsuspected pins (joined by lattice edges) are
// suspect too: an island ringed by lost pins has no boundary that could show its slip.
#include <array>
#include <utility>
#include <vector>

#include "core/tracking/pin_tracker.hpp"

namespace sb {

struct LatticeCheckOptions {
  // First-ring relative step above which a pair is a slip. A slip by one site gives >= ~1 (a lattice
  // vector over one pitch); docs/tracking.md has the measured distribution on correctly tracked images.
  double max_relative_step = 0.6;
  double gabriel_margin = 0.7;           // a detection within this fraction of the half-segment of the middle
  double max_coherent_prior_miss = 0.5;  // pitches; only used when a prior is given
  double max_prior_miss = 0.5;           // pitches; counted only
};

struct LatticeCheckResult {
  int pairs_checked = 0;
  int slipped_pairs = 0;  // first-ring pairs with a relative step above max_relative_step
  int triangles_checked = 0;
  int flipped_triangles = 0;          // rest triangles whose deformed orientation reversed (pins crossed)
  int skipped_sites = 0;              // first-ring pairs with a detected pin between their matches (topology)
  int prior_misses = 0;               // tracked pins farther than max_prior_miss pitches from the prior (counted)
  double median_prior_miss_px = 0;    // median |tracked - prior| (0 without a prior)
  double coherent_prior_miss_px = 0;  // |component-wise median of (tracked - prior)|: a whole-field slip
  int registration_margin = 0;        // pins explained beyond the best one-site translation (see above), after
                                      // the local tests' suspects are dropped
  bool field_shifted = false;         // margin <= 0 or a coherent prior miss: all tracked pins suspect
  int detached_pins = 0;              // tracked pins cut off from the main field by lost or suspect pins (suspect)
  double worst_relative_step = 0;
  // Per pin: on a slipped pair, a skipped site or a flipped triangle, in a shifted field, or detached.
  // Detached pins are unverified rather than evidence of a slip, so they do not make the field unclean.
  std::vector<char> suspect;
  bool clean() const { return slipped_pairs == 0 && skipped_sites == 0 && flipped_triangles == 0 && !field_shifted; }
};

// Lattice edges: first-ring rest pairs (i < j) with no rest pin inside the circle on their segment (where
// the rim's perspective shrinks the pitch, a pin 1.6 median pitches away can be a second neighbour).
std::vector<std::pair<int, int>> lattice_edges(const PinReference& ref);

// Rest triangles of the lattice: Delaunay triangles of the rest pins whose three edges are first-ring
// neighbours (the hexagonal cells; the long triangles along the convex hull are left out). Vertices
// counter-clockwise in image coordinates (positive signed area with v down).
std::vector<std::array<int, 3>> lattice_triangles(const PinReference& ref);

// `disp` with every suspect pin lost (NaN).
std::vector<Vec2> without_suspects(const std::vector<Vec2>& disp, const LatticeCheckResult& check);

// The registration margin alone (see the file comment).
int registration_margin(const PinReference& ref, const std::vector<Vec2>& disp,
                        const std::vector<PinDetection>& detections);

// `disp`: one entry per reference pin, NaN where lost (lost pins are not checked). `detections`: every
// pin detected in the image (matched or not). `prior`: empty or one entry per pin.
LatticeCheckResult check_lattice(const PinReference& ref, const std::vector<Vec2>& disp,
                                 const std::vector<PinDetection>& detections, const LatticeCheckOptions& options = {},
                                 const std::vector<Vec2>& prior = {});

}  // namespace sb
