#pragma once
// Outputs are written atomically: into a temporary file beside the target, then renamed, so a
// reader (or a crash) never sees a half-written file.
#include <filesystem>
#include <functional>
#include <ostream>

namespace cf::graph {

// Calls `write` with a binary stream to a temporary file in the target's directory, flushes,
// checks the stream, and renames it to `path`. Creates parent directories. Throws
// std::runtime_error naming the path on any failure (and removes the temporary file).
void write_atomically(const std::filesystem::path& path, const std::function<void(std::ostream&)>& write);

// For writers that only take a file name (e.g. libraries): `write` gets a temporary path in the
// same directory; after it returns the file is renamed to `path`.
void write_atomically_via_path(const std::filesystem::path& path,
                               const std::function<void(const std::filesystem::path& tmp)>& write);

// For a run abandoned after Ctrl-C (runtime/cancel_deadline.hpp): removes every temporary file a
// writer has open now, and from then on only the calling thread may rename files into place (any
// other writer throws and removes its temporary), so the process can exit without waiting for them.
// Returns how many temporaries were removed.
int abandon_pending_writes();

}  // namespace cf::graph
