#include "nodes/export/glb_builder.hpp"

#include <algorithm>
#include <limits>

namespace cf {

GlbBuilder::GlbBuilder() {
    model.asset.version = "2.0";
    model.asset.generator = "crackflow";
    model.buffers.emplace_back();
}

int GlbBuilder::add_view(const void* data, std::size_t bytes, int target) {
    std::vector<unsigned char>& buf = model.buffers[0].data;
    while (buf.size() % 4) buf.push_back(0);  // accessors of 4-byte components start 4-byte aligned
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = buf.size();
    view.byteLength = bytes;
    view.target = target;
    const auto* p = static_cast<const unsigned char*>(data);
    buf.insert(buf.end(), p, p + bytes);
    model.bufferViews.push_back(std::move(view));
    return static_cast<int>(model.bufferViews.size()) - 1;
}

int GlbBuilder::add_floats(const std::vector<float>& values, int components, int type, int target, bool bounds) {
    tinygltf::Accessor acc;
    acc.bufferView = add_view(values.data(), values.size() * sizeof(float), target);
    acc.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
    acc.type = type;
    acc.count = values.size() / static_cast<std::size_t>(components);
    if (bounds) {
        acc.minValues.assign(std::size_t(components), std::numeric_limits<double>::infinity());
        acc.maxValues.assign(std::size_t(components), -std::numeric_limits<double>::infinity());
        for (std::size_t i = 0; i < values.size(); ++i) {
            const std::size_t c = i % std::size_t(components);
            acc.minValues[c] = std::min(acc.minValues[c], double(values[i]));
            acc.maxValues[c] = std::max(acc.maxValues[c], double(values[i]));
        }
    }
    model.accessors.push_back(std::move(acc));
    return static_cast<int>(model.accessors.size()) - 1;
}

int GlbBuilder::add_indices(const std::vector<std::uint32_t>& indices) {
    tinygltf::Accessor acc;
    acc.bufferView = add_view(indices.data(), indices.size() * sizeof(std::uint32_t), TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    acc.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
    acc.type = TINYGLTF_TYPE_SCALAR;
    acc.count = indices.size();
    model.accessors.push_back(std::move(acc));
    return static_cast<int>(model.accessors.size()) - 1;
}

int GlbBuilder::add_material(const std::string& name, const Vec3& rgb) {
    tinygltf::Material mat;
    mat.name = name;
    mat.pbrMetallicRoughness.baseColorFactor = {rgb.x(), rgb.y(), rgb.z(), 1.0};
    mat.pbrMetallicRoughness.metallicFactor = 0.0;
    mat.pbrMetallicRoughness.roughnessFactor = 0.8;
    model.materials.push_back(std::move(mat));
    return static_cast<int>(model.materials.size()) - 1;
}

}  // namespace cf
