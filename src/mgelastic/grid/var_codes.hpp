#pragma once
// The variable codes of a level: one 16-bit code per lattice point (cell) k that holds, for
// each variable indexed by k (the lower faces u_0..u_{Dim-1} of cell k and its center p, field
// f = 0..Dim), the variable's kind (VarKind, Sec. 5.1) and the smoother that relaxes the equation
// collocated with it (Relaxation). Field f owns bits 4f..4f+3:
//
//   bits 4f, 4f+1: VarKind      bits 4f+2, 4f+3: Relaxation
//
// Two bytes per cell replace one byte per variable for each of kind and relaxation (8 bytes per
// cell in 3D; 2.1 bytes per unknown on the 128^3 box). A code of 0 is a cell with no variable
// (INACTIVE and NONE throughout), so the dead chunks of an embedded body hold zeros.
//
// The double solution level of a mixed-precision solve and the float finest level have the same
// codes: share_from() makes one read the other's array (copies are deep, so a copied level can
// be edited on its own; owns() tells the memory accounting which of the two counts it).
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace mgelastic::grid {

// Sec. 5.1: interior variables lie strictly inside the interior region; boundary variables are
// referenced by interior equations and touch a Dirichlet cell (DIRICHLET) or not (TRACTION).
enum class VarKind : std::uint8_t { INACTIVE = 0, INTERIOR = 1, DIRICHLET = 2, TRACTION = 3 };

// Which smoother relaxes the equation collocated with an interior variable.
enum class Relaxation : std::uint8_t { NONE = 0, DISTRIBUTIVE = 1, BAND = 2 };

using VarCode = std::uint16_t;

constexpr VarCode kind_mask(int field) {
  return static_cast<VarCode>(0x3u << (4 * field));
}
constexpr VarCode relaxation_mask(int field) {
  return static_cast<VarCode>(0xCu << (4 * field));
}
constexpr VarCode kind_bits(int field, VarKind kind) {
  return static_cast<VarCode>(static_cast<unsigned>(kind) << (4 * field));
}
constexpr VarCode relaxation_bits(int field, Relaxation relaxation) {
  return static_cast<VarCode>(static_cast<unsigned>(relaxation) << (4 * field + 2));
}
constexpr VarKind kind_of(VarCode code, int field) {
  return static_cast<VarKind>((code >> (4 * field)) & 0x3u);
}
constexpr Relaxation relaxation_of(VarCode code, int field) {
  return static_cast<Relaxation>((code >> (4 * field + 2)) & 0x3u);
}

// Whether test(codes[i]) holds for any of n codes: a byte-wise OR, which vectorizes (with a bool
// accumulator GCC kept a scalar compare per entry). The kernels skip chunks and rows outside an
// embedded body (most of its bounding box) with it.
template <typename Test>
inline bool any_code(const VarCode* codes, std::ptrdiff_t n, Test test) {
  unsigned char any = 0;
#pragma omp simd reduction(| : any)
  for (std::ptrdiff_t i = 0; i < n; ++i) any |= static_cast<unsigned char>(test(codes[i]));
  return any != 0;
}
// Whether any of n codes has one of `bits` set.
inline bool any_bits(const VarCode* codes, std::ptrdiff_t n, VarCode bits) {
  return any_code(codes, n, [bits](VarCode code) { return (code & bits) != 0; });
}
inline bool any_kind(const VarCode* codes, std::ptrdiff_t n, int field, VarKind kind) {
  const VarCode mask = kind_mask(field), wanted = kind_bits(field, kind);
  return any_code(codes, n, [=](VarCode code) { return (code & mask) == wanted; });
}
inline bool any_relaxation(const VarCode* codes, std::ptrdiff_t n, int field,
                           Relaxation relaxation) {
  const VarCode mask = relaxation_mask(field), wanted = relaxation_bits(field, relaxation);
  return any_code(codes, n, [=](VarCode code) { return (code & mask) == wanted; });
}

// One field's kinds as an indexable view of the codes: kinds[i] = kind_of(codes[i], field).
struct FieldKinds {
  const VarCode* codes;
  int field;
  VarKind operator[](std::ptrdiff_t i) const { return kind_of(codes[i], field); }
  FieldKinds operator+(std::ptrdiff_t offset) const { return {codes + offset, field}; }
  bool any(std::ptrdiff_t n, VarKind kind) const { return any_kind(codes, n, field, kind); }
};

class VarCodes {
 public:
  using Codes = std::vector<VarCode>;

  VarCodes() : m_codes(std::make_shared<Codes>()) {}
  VarCodes(const VarCodes& other) : m_codes(std::make_shared<Codes>(*other.m_codes)) {}
  VarCodes(VarCodes&& other) noexcept;
  VarCodes& operator=(const VarCodes& other);
  VarCodes& operator=(VarCodes&& other) noexcept;

  // n codes of 0 (every variable INACTIVE, no relaxation), on huge pages (huge_pages.hpp).
  void assign(std::size_t n);
  std::size_t size() const { return m_codes->size(); }
  const VarCode* data() const { return m_codes->data(); }
  const Codes& codes() const { return *m_codes; }
  FieldKinds kinds(int field) const { return {data(), field}; }
  std::size_t bytes() const { return m_codes->capacity() * sizeof(VarCode); }

  VarKind kind(int field, std::ptrdiff_t k) const { return kind_of(at(k), field); }
  Relaxation relaxation(int field, std::ptrdiff_t k) const { return relaxation_of(at(k), field); }
  void set_kind(int field, std::ptrdiff_t k, VarKind kind) {
    VarCode& code = (*m_codes)[static_cast<std::size_t>(k)];
    code = static_cast<VarCode>((code & ~kind_mask(field)) | kind_bits(field, kind));
  }
  void set_relaxation(int field, std::ptrdiff_t k, Relaxation relaxation) {
    VarCode& code = (*m_codes)[static_cast<std::size_t>(k)];
    code =
        static_cast<VarCode>((code & ~relaxation_mask(field)) | relaxation_bits(field, relaxation));
  }
  // How many variables of `field` are of `kind`.
  std::size_t count(int field, VarKind kind) const;

  // Reads `other`'s codes from now on; this object's own are freed.
  void share_from(const VarCodes& other) {
    m_codes = other.m_codes;
    m_owner = false;
  }
  bool owns() const { return m_owner; }
  bool same_values(const VarCodes& other) const { return *m_codes == *other.m_codes; }

 private:
  VarCode at(std::ptrdiff_t k) const { return (*m_codes)[static_cast<std::size_t>(k)]; }

  std::shared_ptr<Codes> m_codes;
  bool m_owner = true;
};

}  // namespace mgelastic::grid
