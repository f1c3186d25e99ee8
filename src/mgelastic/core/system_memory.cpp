#include "mgelastic/core/system_memory.hpp"

#include <sys/resource.h>

#include <unistd.h>

#include <fstream>
#include <sstream>

namespace mgelastic {

SystemMemory available_memory() {
  std::ifstream meminfo("/proc/meminfo");
  std::string line;
  while (std::getline(meminfo, line)) {
    std::istringstream fields(line);
    std::string key;
    std::uint64_t kib = 0;
    if (fields >> key >> kib && key == "MemAvailable:")
      return {kib * 1024, "MemAvailable in /proc/meminfo"};
  }
  const long pages = sysconf(_SC_PHYS_PAGES), page_size = sysconf(_SC_PAGESIZE);
  if (pages > 0 && page_size > 0)
    return {static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(page_size),
            "physical memory (sysconf)"};
  return {};
}

std::uint64_t peak_resident_bytes() {
  rusage usage{};
  if (getrusage(RUSAGE_SELF, &usage) != 0) return 0;
  return static_cast<std::uint64_t>(usage.ru_maxrss) * 1024;  // kilobytes on Linux
}

}  // namespace mgelastic
