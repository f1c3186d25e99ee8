#pragma once
// Per-field arrays (one std::vector per field) that two levels on the same lattice and typing
// may hold once: the double solution level of a mixed-precision solve and the float finest
// level have the same variable kinds and relaxation classes (one byte per variable and field
// each, ~2.4 bytes per unknown on the 128^3 box and ~18 on the armadillo at 256 when held twice).
//
// Copies are deep, so a copied level can be edited on its own; share_from() makes this object
// read the other's arrays (an edit through either is then seen by both), and owns() tells the
// memory accounting which of the two counts them.
#include <array>
#include <cstddef>
#include <memory>
#include <vector>

namespace mgelastic::grid {

template <typename T, std::size_t Fields>
class SharedFieldArrays {
 public:
  using Arrays = std::array<std::vector<T>, Fields>;

  SharedFieldArrays() : m_arrays(std::make_shared<Arrays>()) {}
  SharedFieldArrays(const SharedFieldArrays& other)
      : m_arrays(std::make_shared<Arrays>(*other.m_arrays)) {}
  SharedFieldArrays(SharedFieldArrays&& other) noexcept
      : m_arrays(std::move(other.m_arrays)), m_owner(other.m_owner) {
    other.m_arrays = std::make_shared<Arrays>();
    other.m_owner = true;
  }
  SharedFieldArrays& operator=(const SharedFieldArrays& other) {
    if (this != &other) {
      m_arrays = std::make_shared<Arrays>(*other.m_arrays);
      m_owner = true;
    }
    return *this;
  }
  SharedFieldArrays& operator=(SharedFieldArrays&& other) noexcept {
    if (this != &other) {
      m_arrays = std::move(other.m_arrays);
      m_owner = other.m_owner;
      other.m_arrays = std::make_shared<Arrays>();
      other.m_owner = true;
    }
    return *this;
  }

  std::vector<T>& operator[](std::size_t field) { return (*m_arrays)[field]; }
  const std::vector<T>& operator[](std::size_t field) const { return (*m_arrays)[field]; }
  auto begin() { return m_arrays->begin(); }
  auto end() { return m_arrays->end(); }
  auto begin() const { return m_arrays->cbegin(); }
  auto end() const { return m_arrays->cend(); }
  static constexpr std::size_t size() { return Fields; }

  // Reads `other`'s arrays from now on; this object's own are freed.
  void share_from(const SharedFieldArrays& other) {
    m_arrays = other.m_arrays;
    m_owner = false;
  }
  bool owns() const { return m_owner; }
  bool same_values(const SharedFieldArrays& other) const { return *m_arrays == *other.m_arrays; }

 private:
  std::shared_ptr<Arrays> m_arrays;
  bool m_owner = true;
};

}  // namespace mgelastic::grid
