#pragma once
// Bit-for-bit comparison of two OpenVDB float trees for the segmentation tests (includes OpenVDB).
#include <openvdb/openvdb.h>

#include <cstring>
#include <string>

namespace cf::testing {

inline std::string coord_text(const openvdb::Coord& c) {
    return "(" + std::to_string(c[0]) + ", " + std::to_string(c[1]) + ", " + std::to_string(c[2]) + ")";
}

// Every value of both trees in iteration order, with its extent (voxel or tile), active state
// and bits. Returns an empty string when identical, else the first difference.
inline std::string tree_difference(const openvdb::FloatGrid& a, const openvdb::FloatGrid& b) {
    if (a.tree().leafCount() != b.tree().leafCount()) return "leaf counts differ";
    if (a.tree().activeVoxelCount() != b.tree().activeVoxelCount()) return "active voxel counts differ";
    auto ia = a.tree().cbeginValueAll();
    auto ib = b.tree().cbeginValueAll();
    for (; ia && ib; ++ia, ++ib) {
        const float va = *ia, vb = *ib;
        if (ia.getBoundingBox() != ib.getBoundingBox()) return "extent differs at " + coord_text(ia.getCoord());
        if (ia.isValueOn() != ib.isValueOn()) return "active state differs at " + coord_text(ia.getCoord());
        if (std::memcmp(&va, &vb, sizeof va) != 0) return "value differs at " + coord_text(ia.getCoord());
    }
    if (ia || ib) return "value counts differ";
    if (a.getName() != b.getName()) return "names differ";
    return "";
}

}  // namespace cf::testing
