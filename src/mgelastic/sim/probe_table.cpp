#include "mgelastic/sim/probe_table.hpp"

#include <cstdio>
#include <fstream>

#include "mgelastic/io/atomic_file.hpp"
#include "mgelastic/sim/constraint_reactions.hpp"
#include "mgelastic/sim/simulation.hpp"

namespace mgelastic::sim {
namespace {

void append_number(std::string& line, double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, ",%.9g", value);
  line += buffer;
}

std::string header(const Simulation& simulation, std::size_t reactions) {
  std::string line = "frame,time";
  for (const auto& probe : simulation.scene().probes)
    for (const char* column : {"ux", "uy", "uz", "von_mises", "pressure"})
      line += "," + probe.name + "." + column;
  for (std::size_t c = 0; c < reactions; ++c)
    for (const char* column : {"fx", "fy", "fz", "mx", "my", "mz"})
      line += ",reaction" + std::to_string(c) + "." + column;
  return line;
}

}  // namespace

void ProbeTable::add(const Simulation& simulation, int frame, double time) {
  m_samples = sample_probes(simulation);
  m_reactions = constraint_reactions(simulation);
  const std::size_t reactions = m_reactions ? m_reactions->size() : 0;
  m_header = header(simulation, reactions);
  std::string line = std::to_string(frame);
  append_number(line, time);
  for (const ProbeSample& s : m_samples) {
    for (int a = 0; a < 3; ++a) append_number(line, s.displacement[a]);
    append_number(line, s.von_mises);
    append_number(line, s.pressure);
  }
  for (std::size_t c = 0; c < reactions; ++c) {
    const Reaction& r = (*m_reactions)[c];
    for (int a = 0; a < 3; ++a) append_number(line, r.force[a]);
    for (int a = 0; a < 3; ++a) append_number(line, r.moment[a]);
  }
  m_rows.push_back(std::move(line));
}

void ProbeTable::keep_rows_before(const std::filesystem::path& path, int frame) {
  std::ifstream in(path);
  std::string line;
  if (!std::getline(in, line)) return;  // no file, or empty
  while (std::getline(in, line)) {
    const auto comma = line.find(',');
    if (comma == std::string::npos) continue;
    try {
      if (std::stoi(line.substr(0, comma)) < frame) m_rows.push_back(line);
    } catch (const std::exception&) {  // a damaged line: dropped, the frames are recomputed
    }
  }
}

void ProbeTable::write(const std::filesystem::path& path) const {
  io::write_file_atomically(path, [&](std::ostream& out) {
    out << m_header << '\n';
    for (const std::string& row : m_rows) out << row << '\n';
  });
}

}  // namespace mgelastic::sim
