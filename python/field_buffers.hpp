#pragma once
// Live numpy views of a simulation's fields. Each field asked for gets a buffer that lives as long
// as the Python Simulation; after every step the buffers are refilled in place, so an array handed
// out once shows the current frame from then on (copy() it to keep a frame). The library computes
// the grid engine's nodal and cell fields from its staggered unknowns on demand, so a view of
// library memory would not outlive the step; one copy per step of the fields in use is the price.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstddef>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace mgelastic::python {

class FieldBuffers {
 public:
  // Fills `bytes` bytes at the pointer with the field's current values.
  using Fill = std::function<void(std::byte*)>;
  struct Layout {
    char format;  // numpy type character: 'd' float64, 'B' uint8, 'i' int32
    std::vector<pybind11::ssize_t> shape, strides;  // strides in bytes
    std::size_t bytes;
  };

  // A read-only array viewing field `name` (made and filled on first use by `layout` / `fill`);
  // `owner` (the Python Simulation) is kept alive by the array.
  pybind11::array view(const std::string& name, const std::function<Layout()>& layout, Fill fill,
                       pybind11::handle owner);
  // Refills every field handed out (after a step).
  void refresh();

 private:
  struct Field {
    Layout layout;
    std::vector<std::byte> data;
    Fill fill;
  };
  std::map<std::string, Field> m_fields;
};

// A read-only array of `layout` over memory that `owner` keeps alive.
pybind11::array read_only_view(const FieldBuffers::Layout& layout, const void* data,
                               pybind11::handle owner);

}  // namespace mgelastic::python
