#include "field_buffers.hpp"

namespace py = pybind11;

namespace mgelastic::python {

py::array read_only_view(const FieldBuffers::Layout& layout, const void* data, py::handle owner) {
  py::array a(py::dtype(std::string(1, layout.format)), layout.shape, layout.strides, data, owner);
  py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return a;
}

py::array FieldBuffers::view(const std::string& name, const std::function<Layout()>& layout,
                             Fill fill, py::handle owner) {
  auto it = m_fields.find(name);
  if (it == m_fields.end()) {
    Field f{layout(), {}, std::move(fill)};
    f.data.resize(f.layout.bytes);
    f.fill(f.data.data());
    it = m_fields.emplace(name, std::move(f)).first;
  }
  return read_only_view(it->second.layout, it->second.data.data(), owner);
}

void FieldBuffers::refresh() {
  for (auto& [name, field] : m_fields) field.fill(field.data.data());
}

}  // namespace mgelastic::python
