#pragma once
// Transparent huge pages for the crackflow process, decided once at start-up. The executable asks
// jemalloc for them (runtime/heap_config.cpp): one fault per 2 MiB instead of 512 was 8 % of a run
// on a host where faults are slow. On a virtual machine whose host takes back free guest memory
// (virtio-balloon free page reporting) they cost more than they save: free 2 MiB blocks are exactly
// what the guest reports and the host discards, so every huge-page fault is a fresh host fault and a
// 2 MiB clear at a fraction of memory speed, while 4 KiB faults mostly reuse pages still backed
// (docs/performance.md, "Huge pages off where the host reclaims free memory").
#include <filesystem>
#include <string>

namespace cf::runtime {

// Whether a virtio balloon among the devices under `virtio_devices` (sysfs' /sys/bus/virtio/devices:
// one directory per device with `device`, the device id, and `features`, one '0'/'1' per negotiated
// feature bit, bit 0 first) has negotiated free page reporting (device id 5, feature bit 5,
// VIRTIO_BALLOON_F_REPORTING). False when the directory or its files are missing or unreadable.
bool host_reclaims_free_memory(const std::filesystem::path& virtio_devices);

// Called first in main: turns transparent huge pages off for this process and its children
// (prctl PR_SET_THP_DISABLE) when the host reclaims free memory, unless MALLOC_CONF is set (whoever
// sets it chooses the heap's pages themselves).
void settle_huge_pages(const std::filesystem::path& virtio_devices = "/sys/bus/virtio/devices");

// Why huge pages are off for this process ("" when settle_huge_pages left them alone), for
// report.json's versions.allocator.
std::string huge_pages_note();

}  // namespace cf::runtime
