#include "graph/atomic_write.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

using cf::graph::write_atomically;

TEST(AtomicWrite, WritesCompleteFileAndLeavesNoTemporary) {
    auto dir = std::filesystem::temp_directory_path() / "crackflow-tests" / "atomic";
    std::filesystem::remove_all(dir);
    auto path = dir / "sub" / "out.txt";
    write_atomically(path, [](std::ostream& o) { o << "hello\n"; });
    std::ifstream f(path);
    std::stringstream ss;
    ss << f.rdbuf();
    EXPECT_EQ(ss.str(), "hello\n");
    int files = 0;
    for (auto& e : std::filesystem::directory_iterator(path.parent_path())) (void)e, ++files;
    EXPECT_EQ(files, 1);
}

TEST(AtomicWrite, FailedWriterKeepsThePreviousFile) {
    auto dir = std::filesystem::temp_directory_path() / "crackflow-tests" / "atomic2";
    std::filesystem::remove_all(dir);
    auto path = dir / "out.txt";
    write_atomically(path, [](std::ostream& o) { o << "old\n"; });
    EXPECT_THROW(write_atomically(path, [](std::ostream& o) {
                     o << "partial";
                     throw std::runtime_error("writer failed");
                 }),
                 std::runtime_error);
    std::ifstream f(path);
    std::string s;
    std::getline(f, s);
    EXPECT_EQ(s, "old");
    int files = 0;
    for (auto& e : std::filesystem::directory_iterator(dir)) (void)e, ++files;
    EXPECT_EQ(files, 1);
}

TEST(AtomicWrite, UnwritableDirectoryGivesAClearError) {
    try {
        write_atomically("/proc/crackflow-cannot-write/x.txt", [](std::ostream& o) { o << "x"; });
        FAIL() << "expected an error";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("/proc/crackflow-cannot-write"), std::string::npos) << e.what();
    }
}
