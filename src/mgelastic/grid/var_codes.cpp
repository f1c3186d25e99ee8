#include "mgelastic/grid/var_codes.hpp"

#include <algorithm>

#include "mgelastic/grid/huge_pages.hpp"

namespace mgelastic::grid {

VarCodes::VarCodes(VarCodes&& other) noexcept
    : m_codes(std::move(other.m_codes)), m_owner(other.m_owner) {
  other.m_codes = std::make_shared<Codes>();
  other.m_owner = true;
}

VarCodes& VarCodes::operator=(const VarCodes& other) {
  if (this != &other) {
    m_codes = std::make_shared<Codes>(*other.m_codes);
    m_owner = true;
  }
  return *this;
}

VarCodes& VarCodes::operator=(VarCodes&& other) noexcept {
  if (this != &other) {
    m_codes = std::move(other.m_codes);
    m_owner = other.m_owner;
    other.m_codes = std::make_shared<Codes>();
    other.m_owner = true;
  }
  return *this;
}

void VarCodes::assign(std::size_t n) {
  m_codes = std::make_shared<Codes>();
  m_owner = true;
  assign_on_huge_pages(*m_codes, n, VarCode{0});
}

std::size_t VarCodes::count(int field, VarKind kind) const {
  const VarCode mask = kind_mask(field), wanted = kind_bits(field, kind);
  return static_cast<std::size_t>(std::count_if(
      m_codes->begin(), m_codes->end(), [&](VarCode code) { return (code & mask) == wanted; }));
}

}  // namespace mgelastic::grid
