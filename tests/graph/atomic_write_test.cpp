#include "graph/atomic_write.hpp"
#include "tests/harness/expect_error.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <sys/stat.h>

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
    EXPECT_TRUE(cf::testing::throws<std::runtime_error>(
        [&] { write_atomically("/proc/crackflow-cannot-write/x.txt", [](std::ostream& o) { o << "x"; }); },
        {"/proc/crackflow-cannot-write"}));
}

// Only regular files are replaced: a directory, a symbolic link or a FIFO at the target is an
// error naming the path and what is there, and nothing is written or left behind.
TEST(AtomicWrite, NonRegularTargetsAreRefused) {
    auto dir = std::filesystem::temp_directory_path() / "crackflow-tests" / "atomic-targets";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir / "a_directory");
    std::ofstream(dir / "real.txt") << "keep\n";
    std::filesystem::create_symlink(dir / "real.txt", dir / "link.txt");
    ASSERT_EQ(::mkfifo((dir / "fifo").c_str(), 0600), 0);
    const std::pair<const char*, const char*> cases[] = {
        {"a_directory", "a directory"}, {"link.txt", "a symbolic link"}, {"fifo", "not a regular file"}};
    for (const auto& [name, what] : cases) {
        const std::filesystem::path target = dir / name;  // C++17 lambdas do not capture structured bindings
        EXPECT_TRUE(cf::testing::throws<std::runtime_error>(
            [&] { write_atomically(target, [](std::ostream& o) { o << "new\n"; }); }, {name, what}));
    }
    std::ifstream f(dir / "real.txt");
    std::string line;
    std::getline(f, line);
    EXPECT_EQ(line, "keep");  // the link's target is untouched
    int files = 0;
    for (auto& e : std::filesystem::directory_iterator(dir)) (void)e, ++files;
    EXPECT_EQ(files, 4);  // no temporary left
}
