// The patch test (validation/patch_test.hpp): a homogeneous strain is reproduced by both engines
// to round-off and solver tolerance.
#include <gtest/gtest.h>

#include "mgelastic/validation/patch_test.hpp"

namespace mgelastic::validation {
namespace {

// The solves run to 1e-13 relative residual; conditioning of an 8^3 problem (~1e2..1e3) leaves
// the error well below 1e-9 of the field.
constexpr double kPatchError = 1e-9;

TEST(PatchTest, GridReproducesAHomogeneousStrain) {
  const PatchTestResult r = patch_test("grid", 8);
  EXPECT_TRUE(r.converged);
  EXPECT_LT(r.max_relative_error, kPatchError);
}

TEST(PatchTest, GridReproducesAHomogeneousStrainNearlyIncompressible) {
  const PatchTestResult r = patch_test("grid", 8, 0.49);
  EXPECT_TRUE(r.converged);
  EXPECT_LT(r.max_relative_error, kPatchError);
}

TEST(PatchTest, TetReproducesAHomogeneousStrain) {
  const PatchTestResult r = patch_test("tet", 4);
  EXPECT_TRUE(r.converged);
  EXPECT_LT(r.max_relative_error, kPatchError);
}

}  // namespace
}  // namespace mgelastic::validation
