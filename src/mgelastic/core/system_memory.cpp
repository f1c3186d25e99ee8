#include "mgelastic/core/system_memory.hpp"

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

}  // namespace mgelastic
