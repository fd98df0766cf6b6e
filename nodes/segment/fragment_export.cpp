#include "nodes/segment/fragment_export.hpp"

#include <cstdio>
#include <stdexcept>

namespace cf {

FragmentExportResult export_fragments(const std::filesystem::path& dir, const Fragments& f,
                                      const FragmentExportOptions& opt) {
    if (f.fragments.empty()) throw std::invalid_argument("there are no fragments to export");
    FragmentExportResult res;
    if (opt.meshes) {
        for (std::size_t i = 0; i < f.fragments.size(); ++i) {
            SurfaceMesh m = level_set_to_mesh(f.fragments[i].grid, opt.adaptivity);
            if (opt.deformation) opt.deformation->apply(m, &res.deformation);
            char name[64];
            std::snprintf(name, sizeof name, "_%03zu.", i);
            const auto path = dir / (opt.prefix + name + to_string(opt.format));
            write_mesh_file(path, m, opt.format, opt.binary);
            res.triangles += m.num_triangles();
            res.files.push_back(path);
        }
    }
    if (opt.vdb) {
        std::vector<std::pair<std::string, LevelSet>> grids;
        for (std::size_t i = 0; i < f.fragments.size(); ++i)
            grids.emplace_back(opt.prefix + std::to_string(i), f.fragments[i].grid);
        const auto path = dir / (opt.prefix + "s.vdb");
        write_vdb(path, grids);
        res.files.push_back(path);
    }
    if (opt.preview) {
        const auto path = dir / (opt.prefix + "s_preview.png");
        render_fragments_preview(path, f, opt.preview_options);
        res.files.push_back(path);
    }
    return res;
}

}  // namespace cf
