#include "nodes/segment/fragments.hpp"

#include "graph/atomic_write.hpp"

#include <iomanip>

namespace cf {

void write_fragments_csv(const std::filesystem::path& path, const Fragments& f) {
    graph::write_atomically(path, [&](std::ostream& os) {
        os << std::setprecision(17);
        os << "index,volume_m3,bbox_min_x,bbox_min_y,bbox_min_z,bbox_max_x,bbox_max_y,bbox_max_z,"
              "centroid_x,centroid_y,centroid_z,active_voxels\n";
        for (std::size_t i = 0; i < f.fragments.size(); ++i) {
            const Fragment& g = f.fragments[i];
            os << i << ',' << g.volume;
            for (const Vec3* v : {&g.bbox.min, &g.bbox.max, &g.centroid})
                for (int a = 0; a < 3; ++a) os << ',' << (*v)[a];
            os << ',' << g.active_voxels << '\n';
        }
    });
}

void write_fragments_json(const std::filesystem::path& path, const Fragments& f) {
    auto vec = [](std::ostream& os, const Vec3& v) { os << '[' << v.x() << ", " << v.y() << ", " << v.z() << ']'; };
    graph::write_atomically(path, [&](std::ostream& os) {
        os << std::setprecision(17);
        os << "{\n  \"voxel_size_m\": " << f.voxel_size << ",\n  \"threshold_m\": " << f.threshold
           << ",\n  \"tile_aware\": " << (f.used_tiles ? "true" : "false") << ",\n  \"fragments\": [";
        for (std::size_t i = 0; i < f.fragments.size(); ++i) {
            const Fragment& g = f.fragments[i];
            os << (i ? ",\n" : "\n") << "    {\"index\": " << i << ", \"volume_m3\": " << g.volume << ", \"bbox_min_m\": ";
            vec(os, g.bbox.min);
            os << ", \"bbox_max_m\": ";
            vec(os, g.bbox.max);
            os << ", \"centroid_m\": ";
            vec(os, g.centroid);
            os << ", \"active_voxels\": " << g.active_voxels << '}';
        }
        os << "\n  ]\n}\n";
    });
}

}  // namespace cf
