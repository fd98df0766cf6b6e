// Huge pages off where the host reclaims free memory (runtime/huge_pages.hpp), on made-up sysfs trees.
#include "runtime/huge_pages.hpp"
#include "tests/harness/node_harness.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;

// One virtio device directory as sysfs shows it: `device` "0x%04x" and `features`, 64 bits as
// '0'/'1' characters, bit 0 first, with the given bits set.
void add_device(const fs::path& root, const std::string& name, unsigned id, std::initializer_list<int> bits) {
    fs::create_directories(root / name);
    char text[16];
    std::snprintf(text, sizeof text, "0x%04x", id);
    std::ofstream(root / name / "device") << text << '\n';
    std::string features(64, '0');
    for (int b : bits) features[std::size_t(b)] = '1';
    std::ofstream(root / name / "features") << features << '\n';
}

// This machine's balloon as read on 2026-12-06: stats queue (1), deflate on OOM (2), free page
// reporting (5), and the transport bits 32 and 35.
constexpr std::initializer_list<int> kReportingBalloon = {1, 2, 5, 32, 35};

// Runs `body` in a child (prctl and MALLOC_CONF are process-wide) and returns its exit code.
template <class F>
int in_child(F body) {
    const pid_t pid = fork();
    if (pid == 0) _exit(body());
    int status = 0;
    waitpid(pid, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace

TEST(HugePages, ABalloonWithFreePageReportingMeansTheHostReclaimsFreeMemory) {
    const fs::path root = cf::testing::temp_dir("virtio-reporting");
    add_device(root, "virtio0", 2, {5, 9, 32});  // a block device: bit 5 means something else there
    EXPECT_FALSE(cf::runtime::host_reclaims_free_memory(root));
    add_device(root, "virtio3", 5, kReportingBalloon);
    EXPECT_TRUE(cf::runtime::host_reclaims_free_memory(root));
}

TEST(HugePages, ABalloonWithoutReportingOrNoBalloonLeavesThePagesAlone) {
    const fs::path root = cf::testing::temp_dir("virtio-plain");
    add_device(root, "virtio0", 5, {1, 2, 32});  // stats and deflate on OOM, no reporting
    add_device(root, "virtio1", 1, {5, 32});     // a network device
    EXPECT_FALSE(cf::runtime::host_reclaims_free_memory(root));
    EXPECT_FALSE(cf::runtime::host_reclaims_free_memory(root / "absent"));
    // A features file cut short before bit 5.
    fs::create_directories(root / "virtio2");
    std::ofstream(root / "virtio2" / "device") << "0x0005\n";
    std::ofstream(root / "virtio2" / "features") << "0110\n";
    EXPECT_FALSE(cf::runtime::host_reclaims_free_memory(root));
}

TEST(HugePages, TurnedOffForTheProcessUnlessMallocConfChoosesThem) {
    const fs::path reporting = cf::testing::temp_dir("virtio-settle");
    add_device(reporting, "virtio0", 5, kReportingBalloon);
    const fs::path plain = cf::testing::temp_dir("virtio-settle-plain");
    add_device(plain, "virtio0", 5, {1, 2});
    // Exit code 0: huge pages off and the report says why; 1: on and no note; 2: not as expected.
    auto settle = [](const fs::path& devices, const char* malloc_conf) {
        return [=] {
            if (malloc_conf) setenv("MALLOC_CONF", malloc_conf, 1);
            else unsetenv("MALLOC_CONF");
            if (prctl(PR_GET_THP_DISABLE, 0, 0, 0, 0) != 0) return 2;  // inherited from whoever ran the test
            cf::runtime::settle_huge_pages(devices);
            const bool off = prctl(PR_GET_THP_DISABLE, 0, 0, 0, 0) == 1;
            const bool noted = cf::runtime::huge_pages_note().find("free page reporting") != std::string::npos;
            return off && noted ? 0 : !off && !noted ? 1 : 2;
        };
    };
    EXPECT_EQ(in_child(settle(reporting, nullptr)), 0);
    EXPECT_EQ(in_child(settle(reporting, "thp:always")), 1);
    EXPECT_EQ(in_child(settle(plain, nullptr)), 1);
}
