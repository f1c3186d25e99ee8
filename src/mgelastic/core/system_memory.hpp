#pragma once
// The machine's memory as the OS reports it, for refusing problems that cannot fit before they
// allocate (scene/grid_memory.hpp).
#include <cstdint>
#include <string>

namespace mgelastic {

struct SystemMemory {
  std::uint64_t bytes = 0;  // 0 = unknown
  std::string source;       // where the number came from, for messages
};

// Memory available for a new process: MemAvailable of /proc/meminfo, else the physical memory
// (sysconf(_SC_PHYS_PAGES) * page size), else 0.
SystemMemory available_memory();

// The process's peak resident memory so far (getrusage's ru_maxrss), bytes; 0 if unknown.
// Monotone over the process: benchmarks that run several sizes report it after each, smallest
// first.
std::uint64_t peak_resident_bytes();

}  // namespace mgelastic
