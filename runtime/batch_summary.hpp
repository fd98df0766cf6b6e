#pragma once
// Results of a batch: the record each row attempt leaves (DIR/<id>/batch_row.json, beside the
// run's own report.json) and the summary of all rows (DIR/summary.json, DIR/summary.csv).
#include <filesystem>
#include <string>
#include <vector>

namespace cf::runtime::batch {

inline constexpr const char* kRowRecord = "batch_row.json";
inline constexpr const char* kRowLog = "batch_row.log";

// What the batch runner saw of one attempt at a row (the process, not the simulation).
struct RowRecord {
    std::string id;
    std::string state;           // "running" while the attempt runs, then "exited" or "signalled"
    int exit_code = -1;          // when exited
    int signal = 0;              // when signalled (e.g. 9: killed)
    std::string host;
    std::string started_utc;
    double seconds = 0;          // process wall time
    long long peak_rss_bytes = 0;  // the process's peak resident set (getrusage of the child)
    std::string job_id, array_job_id, array_task_id;  // Slurm's, when run by Slurm
    int attempt = 0;
};
std::string row_record_json(const RowRecord& r);
bool read_row_record(const std::filesystem::path& file, RowRecord& r);

// One line of the summary.
struct RowResult {
    std::string id;
    // ok; failed (the simulation failed, exit 1, or the process died: see signal); invalid (exit 2:
    // bad input); cancelled (Ctrl-C/SIGTERM, exit 130/143); missing (no report: never ran, or lost).
    std::string status;
    int exit_code = -1;  // -1: unknown (no record)
    int signal = 0;
    std::string error;   // from report.json
    long long fragments = -1, steps = -1;  // -1: not a fracture pipeline, or no report
    double seconds = -1;
    long long peak_rss_bytes = -1;
    std::string host, job_id, array_job_id, array_task_id;
    std::string log;     // path of the row's log
};
RowResult read_row_result(const std::filesystem::path& out_dir, const std::string& id);

struct SummaryCounts {
    int total = 0, ok = 0, failed = 0;  // failed: every row that is not ok (missing ones included)
};
SummaryCounts count(const std::vector<RowResult>& rows);
// The batch's exit code from its rows, the same for every backend and for --collect (docs/batch.md):
// 2 if any row is invalid (bad input), else 1 if any is not ok, else 0.
int batch_exit_code(const std::vector<RowResult>& rows);

std::string summary_json(const std::vector<RowResult>& rows);
std::string summary_csv(const std::vector<RowResult>& rows);

// The ids of the batch in manifest order, stored at DIR/.batch/rows.txt when a batch starts.
std::filesystem::path row_list_file(const std::filesystem::path& out_dir);
void write_row_list(const std::filesystem::path& out_dir, const std::vector<std::string>& ids);
std::vector<std::string> read_row_list(const std::filesystem::path& out_dir);  // throws when absent

// Reads every row, writes summary.json and summary.csv atomically, returns the rows.
std::vector<RowResult> collect(const std::filesystem::path& out_dir);

}  // namespace cf::runtime::batch
