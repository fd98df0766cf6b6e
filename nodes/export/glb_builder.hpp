#pragma once
// The glTF 2.0 model under construction, shared by the .glb writers (write_glb.cpp: one fragment
// mesh; nodes/rigid/animation_gltf.cpp: a rigid-body scene). All binary data goes into buffer 0,
// which becomes the .glb's BIN chunk. tinygltf from Debian's compiled library (no implementation
// macro); only those two writers and this file include it.
#include "nodes/domain/surface_mesh.hpp"

#include <tiny_gltf.h>

#include <cstdint>
#include <string>
#include <vector>

namespace cf {

class GlbBuilder {
public:
    tinygltf::Model model;  // asset "2.0", generator "crackflow", one empty buffer

    GlbBuilder();
    // An accessor of values.size() / components elements; `target` is the buffer view's target
    // (TINYGLTF_TARGET_ARRAY_BUFFER for vertex data, 0 for animation keys); with min/max bounds,
    // which glTF requires for POSITION and animation inputs.
    int add_floats(const std::vector<float>& values, int components, int type, int target, bool bounds);
    int add_indices(const std::vector<std::uint32_t>& indices);
    // A rough, non-metallic material of colour rgb in [0, 1].
    int add_material(const std::string& name, const Vec3& rgb);

private:
    int add_view(const void* data, std::size_t bytes, int target);
};

}  // namespace cf
