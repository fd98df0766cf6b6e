#include "nodes/segment/fragment_export.hpp"

#include "graph/cancel_token.hpp"

#include <tbb/parallel_for.h>
#include <tbb/task_group.h>

#include <cstdio>
#include <exception>
#include <stdexcept>

namespace cf {

FragmentExportResult export_fragments(const std::filesystem::path& dir, const Fragments& f,
                                      const FragmentExportOptions& opt) {
    if (f.fragments.empty()) throw std::invalid_argument("there are no fragments to export");
    FragmentExportResult res;
    // Meshes (one task per fragment, each writing its own file), the VDB and the preview are
    // independent: they run concurrently. Per-fragment figures are summed in fragment order.
    const std::size_t n = f.fragments.size();
    std::vector<std::filesystem::path> mesh_files(opt.meshes ? n : 0);
    std::vector<std::size_t> triangles(mesh_files.size(), 0);
    std::vector<DeformationStats> stats(mesh_files.size());
    std::filesystem::path vdb_path, preview_path;
    tbb::task_group tasks;
    const CancelToken cancel = CancelToken::current();  // polled per fragment mesh
    // A task that throws cancels the task group's context, and with it the parallel loops nested in
    // the other tasks, which then end early without an error: the preview was written half rendered
    // when the VDB write failed. Each task runs in a context of its own, so what it writes is whole.
    auto isolated = [](auto&& body) {
        tbb::task_group_context own(tbb::task_group_context::isolated);
        tbb::task_group group(own);
        group.run_and_wait(body);
    };
    if (opt.vdb)
        tasks.run([&] {
            isolated([&] {
                std::vector<std::pair<std::string, LevelSet>> grids;
                for (std::size_t i = 0; i < n; ++i) grids.emplace_back(opt.prefix + std::to_string(i), f.fragments[i].grid);
                vdb_path = dir / (opt.prefix + "s.vdb");
                write_vdb(vdb_path, grids);
            });
        });
    if (opt.preview)
        tasks.run([&] {
            isolated([&] {
                preview_path = dir / (opt.prefix + "s_preview.png");
                render_fragments_preview(preview_path, f, opt.preview_options);
            });
        });
    std::exception_ptr mesh_error;  // the tasks are waited for before any error leaves this function
    if (opt.meshes) try {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t i = r.begin(); i != r.end(); ++i) {
                cancel.poll();
                SurfaceMesh m = level_set_to_mesh(f.fragments[i].grid, opt.adaptivity);
                if (opt.deformation) opt.deformation->apply(m, &stats[i]);
                char name[64];
                std::snprintf(name, sizeof name, "_%03zu.", i);
                mesh_files[i] = dir / (opt.prefix + name + to_string(opt.format));
                write_mesh_file(mesh_files[i], m, opt.format, opt.binary);
                triangles[i] = m.num_triangles();
            }
        });
    } catch (...) {
        mesh_error = std::current_exception();
    }
    tasks.wait();
    if (mesh_error) std::rethrow_exception(mesh_error);
    for (std::size_t i = 0; i < mesh_files.size(); ++i) {
        res.files.push_back(mesh_files[i]);
        res.triangles += triangles[i];
        res.deformation.add(stats[i]);
    }
    if (opt.vdb) res.files.push_back(vdb_path);
    if (opt.preview) res.files.push_back(preview_path);
    return res;
}

}  // namespace cf
