#pragma once
// Writing .vdb files through the project's checked atomic writer. openvdb::io::File::write
// checks neither its writes nor its close, so a full disk or a file-size limit left a truncated
// object.vdb under its final name. Here the archive goes into graph::write_atomically's stream,
// whose every write and close are checked (with the OS error in the message) before the rename.
// Include only from translation units that already include OpenVDB (it is slow to compile).
#include "graph/atomic_write.hpp"

#include <openvdb/io/Archive.h>
#include <openvdb/openvdb.h>

#include <filesystem>

namespace cf {

// The same layout as io::File writes (seekable: grid offsets filled in), so io::File, Houdini and
// pyopenvdb read it with random access.
class CheckedVdbArchive : public openvdb::io::Archive {
public:
    openvdb::io::Archive::Ptr copy() const override { return std::make_shared<CheckedVdbArchive>(*this); }
    void write_to(std::ostream& os, const openvdb::GridPtrVec& grids) const {
        openvdb::io::Archive::write(os, grids, /*seekable=*/true, openvdb::MetaMap());
    }
};

inline void write_vdb_file_checked(const std::filesystem::path& path, const openvdb::GridPtrVec& grids) {
    graph::write_atomically(path, [&](std::ostream& os) { CheckedVdbArchive().write_to(os, grids); });
}

}  // namespace cf
