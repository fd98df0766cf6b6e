#pragma once
// Which rows still need running, how rows are packed into scheduler tasks and tasks into job
// arrays. Plain functions over numbers and files, tested without a scheduler.
#include "runtime/batch_manifest.hpp"

#include <filesystem>
#include <string>
#include <vector>

namespace cf::runtime::batch {

// A row is complete when DIR/<id>/report.json (written atomically by `crackflow run`) says
// status ok for the same pipeline, overrides and --fast as the manifest row now asks for.
// Returns "ok", or why it is not: "missing", "failed", "cancelled", "stale" (an ok result of other
// parameters), "unreadable".
std::string row_completion(const std::filesystem::path& row_dir, const Row& row, bool fast);

// Rows per scheduler task so that a task's fixed cost (`task_overhead_seconds`: queueing, start,
// process launch) stays below `max_overhead_fraction` of its work.
int rows_per_task(double row_seconds, double task_overhead_seconds, double max_overhead_fraction = 0.05);

// Task k holds rows [k R, (k+1) R): the mapping depends only on the manifest and R, so a retry
// resubmits the same array indices for the same rows.
std::vector<std::vector<std::size_t>> pack_rows(std::size_t rows, int rows_per_task);

// The tasks holding at least one row that is not complete.
std::vector<long> tasks_with_pending_rows(const std::vector<std::vector<std::size_t>>& tasks,
                                          const std::vector<bool>& row_complete);

// One sbatch submission: array indices [0, max_array_size) of tasks offset + index.
struct ArrayChunk {
    long offset = 0;
    std::vector<long> indices;  // sorted, each < max_array_size
    std::string array_spec;     // "0-3,7,9-12" plus "%P" when a limit is given
};
// Task numbers (sorted) split at the cluster's MaxArraySize (indices run 0..MaxArraySize-1).
std::vector<ArrayChunk> split_into_arrays(const std::vector<long>& tasks, long max_array_size, int max_parallel);

// "0-3,7,9-12" of sorted distinct numbers.
std::string index_ranges(const std::vector<long>& sorted);

// MaxArraySize from `scontrol show config` output; `fallback` when absent.
long parse_max_array_size(const std::string& scontrol_config, long fallback = 1001);

}  // namespace cf::runtime::batch
