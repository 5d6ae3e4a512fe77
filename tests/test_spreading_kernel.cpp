// core/effects/spreading_kernel: skin_indentation's Gaussian spreading over the pins, and its sharing.
#include <catch2/catch.hpp>

#include <cmath>

#include "core/effects/spreading_kernel.hpp"

namespace test_spreading_kernel {

namespace {
constexpr double kSigmaM = 0.002;
// Two pins d = sigma sqrt(2 ln 2) apart: exp(-d^2 / (2 sigma^2)) = exp(-ln 2) = 1/2.
std::vector<sb::Vec3> two_pins() { return {{0, 0, 0}, {kSigmaM * std::sqrt(2 * std::log(2.0)), 0, 0}}; }
}  // namespace

TEST_CASE("each row of the kernel is the Gaussian of the distances, normalised to sum 1", "[spreading_kernel]") {
  // Row 0: [1, 1/2] / (3/2) = [2/3, 1/3]; by symmetry row 1 is [1/3, 2/3].
  constexpr double kTol = 1e-12;
  const sb::effects::SpreadingKernel k = sb::effects::spreading_kernel(two_pins(), kSigmaM);
  REQUIRE(k.size() == 4);
  CHECK(std::abs(k[0] - 2.0 / 3) < kTol);
  CHECK(std::abs(k[1] - 1.0 / 3) < kTol);
  CHECK(std::abs(k[2] - 1.0 / 3) < kTol);
  CHECK(std::abs(k[3] - 2.0 / 3) < kTol);
}

TEST_CASE("models of the same pins and width share one kernel; another width builds its own", "[spreading_kernel]") {
  const std::vector<sb::Vec3> pins = two_pins(), same_pins_elsewhere = two_pins();
  auto a = sb::effects::shared_spreading_kernel(pins, kSigmaM);
  auto b = sb::effects::shared_spreading_kernel(same_pins_elsewhere, kSigmaM);  // keyed by value, not address
  CHECK(a.get() == b.get());
  CHECK(a.use_count() == 2);
  auto wider = sb::effects::shared_spreading_kernel(pins, 2 * kSigmaM);
  CHECK(wider.get() != a.get());
  CHECK(*wider != *a);
}

TEST_CASE("a kernel nobody holds is freed; the next model builds it again", "[spreading_kernel]") {
  auto first = sb::effects::shared_spreading_kernel(two_pins(), kSigmaM);
  const sb::effects::SpreadingKernel values = *first;
  first.reset();
  auto again = sb::effects::shared_spreading_kernel(two_pins(), kSigmaM);
  CHECK(again.use_count() == 1);  // no cache kept it alive
  CHECK(*again == values);
}

}  // namespace test_spreading_kernel
