#include "runtime/huge_pages.hpp"

#include <sys/prctl.h>

#include <cstdlib>
#include <fstream>
#include <system_error>

namespace cf::runtime {

namespace {

constexpr unsigned kBalloonDeviceId = 5;       // virtio spec 5.5: traditional memory balloon
constexpr std::size_t kFreePageReporting = 5;  // VIRTIO_BALLOON_F_REPORTING

std::string first_line(const std::filesystem::path& file) {
    std::ifstream in(file);
    std::string line;
    std::getline(in, line);
    return line;
}

bool is_balloon(const std::filesystem::path& device) {
    const std::string id = first_line(device / "device");
    if (id.empty()) return false;
    char* end = nullptr;
    const unsigned long v = std::strtoul(id.c_str(), &end, 16);
    return end != id.c_str() && v == kBalloonDeviceId;
}

std::string& note() {
    static std::string text;
    return text;
}

}  // namespace

bool host_reclaims_free_memory(const std::filesystem::path& virtio_devices) {
    std::error_code ec;
    for (std::filesystem::directory_iterator it(virtio_devices, ec), end; !ec && it != end; it.increment(ec)) {
        if (!is_balloon(it->path())) continue;
        const std::string features = first_line(it->path() / "features");
        if (features.size() > kFreePageReporting && features[kFreePageReporting] == '1') return true;
    }
    return false;
}

void settle_huge_pages(const std::filesystem::path& virtio_devices) {
    if (std::getenv("MALLOC_CONF")) return;
    if (!host_reclaims_free_memory(virtio_devices)) return;
    if (prctl(PR_SET_THP_DISABLE, 1, 0, 0, 0) == 0)
        note() = "huge pages off for this process: the host reclaims free memory (virtio-balloon free page reporting)";
}

std::string huge_pages_note() { return note(); }

}  // namespace cf::runtime
