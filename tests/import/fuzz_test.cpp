// Seeded random mutations (bit flips, byte changes, insertions, deletions, digit swaps,
// truncation) of valid files in every format. Every outcome must be either a valid mesh or a
// MeshFileError whose message names the file; never a crash, another exception or a hang.
// Run the ASan build (-DCRACKFLOW_SANITIZE=ON) to catch out-of-bounds reads too.
#include "nodes/import/read_mesh.hpp"
#include "tests/import/mesh_fixtures.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <random>

namespace cf::testing {
namespace {

struct Sample {
    std::string name, ext, bytes;
};

std::vector<Sample> samples() {
    const SurfaceMesh cube = unit_cube(), tet = tetrahedron();
    return {{"cube.obj", ".obj", cube_obj()},
            {"cube.off", ".off", cube_off()},
            {"cube.ply", ".ply", cube_ply_ascii()},
            {"tet_le.ply", ".ply", mesh_ply_binary(tet, false)},
            {"tet_be.ply", ".ply", mesh_ply_binary(tet, true)},
            {"tet.stl", ".stl", mesh_stl_ascii(tet)},
            {"cube.stl", ".stl", mesh_stl_binary(cube)}};
}

std::string mutate(std::string s, std::mt19937_64& rng) {
    auto pick = [&](std::size_t n) { return n == 0 ? std::size_t(0) : std::size_t(rng() % n); };
    const int ops = 1 + static_cast<int>(rng() % 4);
    for (int op = 0; op < ops; ++op) {
        switch (rng() % 7) {
            case 0:  // flip one bit
                if (!s.empty()) s[pick(s.size())] ^= static_cast<char>(1 << (rng() % 8));
                break;
            case 1:  // overwrite a byte
                if (!s.empty()) s[pick(s.size())] = static_cast<char>(rng() & 0xff);
                break;
            case 2: {  // insert 1..8 random bytes
                std::string ins(1 + rng() % 8, '\0');
                for (char& c : ins) c = static_cast<char>(rng() & 0xff);
                s.insert(pick(s.size() + 1), ins);
                break;
            }
            case 3: {  // delete 1..16 bytes
                if (s.empty()) break;
                std::size_t at = pick(s.size());
                s.erase(at, 1 + rng() % 16);
                break;
            }
            case 4:  // truncate
                s.resize(pick(s.size() + 1));
                break;
            case 5: {  // change a digit (index and count fields in text formats)
                for (int tries = 0; tries < 16 && !s.empty(); ++tries) {
                    std::size_t at = pick(s.size());
                    if (s[at] >= '0' && s[at] <= '9') {
                        s[at] = static_cast<char>('0' + rng() % 10);
                        break;
                    }
                }
                break;
            }
            case 6: {  // duplicate a chunk (repeated lines / records)
                if (s.empty()) break;
                std::size_t at = pick(s.size()), len = 1 + rng() % 64;
                s.insert(pick(s.size() + 1), s.substr(at, len));
                break;
            }
        }
    }
    return s;
}

// A mesh that comes out of the importer must be a usable closed outward surface.
void expect_valid(const SurfaceMesh& m, const std::string& context) {
    ASSERT_GT(m.num_triangles(), 0u) << context;
    ASSERT_EQ(m.region.size(), m.num_triangles()) << context;
    for (const Vec3& p : m.vertices) ASSERT_TRUE(p.allFinite()) << context;
    std::vector<char> used(m.num_vertices(), 0);
    for (const Tri& t : m.triangles)
        for (int v : t) {
            ASSERT_GE(v, 0) << context;
            ASSERT_LT(v, static_cast<int>(m.num_vertices())) << context;
            used[v] = 1;
        }
    for (char u : used) ASSERT_TRUE(u) << context << ": unreferenced vertex kept";
    EXPECT_GT(signed_volume(m), 0.0) << context;
}

TEST(ImportFuzz, MutatedFilesGiveAMeshOrAClearError) {
    // CI runs a fixed, seeded 3000 mutations per sample (about a second); a deeper local run:
    // CRACKFLOW_FUZZ_ITERATIONS=100000 CRACKFLOW_FUZZ_SEED=5 test_import_algorithms
    const char* env_n = std::getenv("CRACKFLOW_FUZZ_ITERATIONS");
    const char* env_seed = std::getenv("CRACKFLOW_FUZZ_SEED");
    const int iterations_per_sample = env_n ? std::atoi(env_n) : 3000;
    std::mt19937_64 rng(env_seed ? std::strtoull(env_seed, nullptr, 10) : 20261122u);
    const auto start = std::chrono::steady_clock::now();
    std::size_t accepted = 0, rejected = 0;
    double slowest = 0;
    auto dir = std::filesystem::temp_directory_path() / "crackflow-tests" / "import-fuzz";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    for (const Sample& s : samples()) {
        for (int i = 0; i < iterations_per_sample; ++i) {
            const std::string bytes = mutate(s.bytes, rng);
            ImportOptions o;
            o.reorient = rng() % 2;
            o.weld_tolerance = rng() % 4 == 0 ? 1e-6 : 0.0;
            const std::string context = s.name + " iteration " + std::to_string(i);
            const auto t0 = std::chrono::steady_clock::now();
            try {
                SurfaceMesh m;
                if (i % 100 == 0) {  // now and then through a real file, to cover the file layer
                    m = read_mesh(write_file(dir / s.name, bytes), o);
                } else {
                    m = build_surface_mesh(read_mesh_soup(s.name, s.ext, bytes), o).mesh;
                }
                expect_valid(m, context);
                ++accepted;
            } catch (const MeshFileError& e) {
                const std::string msg = e.what();
                EXPECT_NE(msg.find(s.name), std::string::npos) << context << ": " << msg;
                EXPECT_NE(msg.find(": error: "), std::string::npos) << context << ": " << msg;
                ++rejected;
            } catch (const std::exception& e) {
                ADD_FAILURE() << context << ": unexpected " << typeid(e).name() << ": " << e.what();
            }
            slowest = std::max(slowest, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        }
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("fuzz: %zu inputs, %zu accepted, %zu rejected, %.2f s, slowest %.4f s\n", accepted + rejected, accepted,
                rejected, seconds, slowest);
    EXPECT_EQ(accepted + rejected, samples().size() * iterations_per_sample);
    EXPECT_GT(accepted, 0u);  // some mutations are harmless (comments, normals): they must still load
    EXPECT_LT(slowest, 1.0);  // no input may make the reader crawl (hang guard)
}

}  // namespace
}  // namespace cf::testing
