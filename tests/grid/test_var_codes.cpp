#include "mgelastic/grid/var_codes.hpp"

#include <gtest/gtest.h>

#include <array>

namespace mgelastic::grid {
namespace {

constexpr std::array<VarKind, 4> kKinds{VarKind::INACTIVE, VarKind::INTERIOR, VarKind::DIRICHLET,
                                        VarKind::TRACTION};
constexpr std::array<Relaxation, 3> kRelaxations{Relaxation::NONE, Relaxation::DISTRIBUTIVE,
                                                 Relaxation::BAND};

// Every field's kind and relaxation round-trip whatever the other fields hold: the four-bit
// fields of one code do not overlap.
TEST(VarCodes, FieldsOfOneCodeAreIndependent) {
  VarCodes codes;
  codes.assign(3);
  for (int f = 0; f < 4; ++f) {
    EXPECT_EQ(codes.kind(f, 1), VarKind::INACTIVE);
    EXPECT_EQ(codes.relaxation(f, 1), Relaxation::NONE);
  }
  for (int pass = 0; pass < 2; ++pass) {
    for (int f = 0; f < 4; ++f) {
      codes.set_kind(f, 1, kKinds[(f + pass) % 4]);
      codes.set_relaxation(f, 1, kRelaxations[(2 * f + pass) % 3]);
    }
    for (int f = 0; f < 4; ++f) {
      EXPECT_EQ(codes.kind(f, 1), kKinds[(f + pass) % 4]) << f;
      EXPECT_EQ(codes.relaxation(f, 1), kRelaxations[(2 * f + pass) % 3]) << f;
    }
  }
  EXPECT_EQ(codes.data()[0], 0);  // neighbors untouched
  EXPECT_EQ(codes.data()[2], 0);
}

TEST(VarCodes, ScansFindTheWantedFieldOnly) {
  VarCodes codes;
  codes.assign(40);
  codes.set_kind(2, 33, VarKind::INTERIOR);
  codes.set_relaxation(2, 33, Relaxation::BAND);
  EXPECT_TRUE(any_kind(codes.data(), 40, 2, VarKind::INTERIOR));
  EXPECT_FALSE(any_kind(codes.data(), 33, 2, VarKind::INTERIOR));
  EXPECT_FALSE(any_kind(codes.data(), 40, 1, VarKind::INTERIOR));
  EXPECT_FALSE(any_kind(codes.data(), 40, 3, VarKind::INTERIOR));
  EXPECT_TRUE(any_relaxation(codes.data(), 40, 2, Relaxation::BAND));
  EXPECT_FALSE(any_relaxation(codes.data(), 40, 2, Relaxation::DISTRIBUTIVE));
  EXPECT_FALSE(any_bits(codes.data(), 40, relaxation_bits(2, Relaxation::DISTRIBUTIVE)));
  EXPECT_EQ(codes.count(2, VarKind::INTERIOR), 1u);
  EXPECT_EQ(codes.count(2, VarKind::INACTIVE), 39u);
  const FieldKinds kinds = codes.kinds(2);
  EXPECT_EQ((kinds + 30)[3], VarKind::INTERIOR);
  EXPECT_EQ(kinds[32], VarKind::INACTIVE);
}

TEST(VarCodes, SharedCodesAreOneArrayAndCopiesAreDeep) {
  VarCodes fine;
  fine.assign(8);
  VarCodes solution;
  solution.assign(8);
  ASSERT_TRUE(solution.same_values(fine));
  solution.share_from(fine);
  EXPECT_FALSE(solution.owns());
  EXPECT_EQ(solution.data(), fine.data());
  fine.set_kind(1, 4, VarKind::DIRICHLET);
  EXPECT_EQ(solution.kind(1, 4), VarKind::DIRICHLET);
  VarCodes copy = solution;
  EXPECT_TRUE(copy.owns());
  EXPECT_NE(copy.data(), fine.data());
  copy.set_kind(1, 4, VarKind::TRACTION);
  EXPECT_EQ(fine.kind(1, 4), VarKind::DIRICHLET);
  const VarCodes moved = std::move(copy);
  EXPECT_EQ(moved.kind(1, 4), VarKind::TRACTION);
}

}  // namespace
}  // namespace mgelastic::grid
