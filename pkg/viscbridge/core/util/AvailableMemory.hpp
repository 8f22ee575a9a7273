// The memory a new allocation can take without swapping or the kernel's OOM killer: Linux's own
// estimate, MemAvailable in /proc/meminfo (free memory plus the page cache it can drop), else the
// free pages.  YADE-free.
#pragma once
#include <cstddef>
#include <fstream>
#include <string>
#include <unistd.h>

namespace viscbridge {

inline size_t availableMemoryBytes()
{
	std::ifstream meminfo("/proc/meminfo");
	std::string   key;
	size_t        kib = 0;
	while (meminfo >> key >> kib)
		if (key == "MemAvailable:") return kib * 1024;
		else meminfo.ignore(256, '\n');
	return static_cast<size_t>(sysconf(_SC_AVPHYS_PAGES)) * static_cast<size_t>(sysconf(_SC_PAGESIZE));
}

} // namespace viscbridge
