#include "runtime/batch_summary.hpp"

#include "graph/atomic_write.hpp"
#include "graph/json_writer.hpp"

#include <yaml-cpp/yaml.h>

#include <fstream>
#include <sstream>
#include <stdexcept>

namespace cf::runtime::batch {

namespace fs = std::filesystem;

std::string row_record_json(const RowRecord& r) {
    graph::JsonWriter w;
    w.begin_object();
    w.key("id").value(r.id);
    w.key("state").value(r.state);
    w.key("exit_code").value(r.exit_code);
    w.key("signal").value(r.signal);
    w.key("host").value(r.host);
    w.key("started_utc").value(r.started_utc);
    w.key("seconds").value(r.seconds);
    w.key("peak_rss_bytes").value(r.peak_rss_bytes);
    w.key("slurm_job_id").value(r.job_id);
    w.key("slurm_array_job_id").value(r.array_job_id);
    w.key("slurm_array_task_id").value(r.array_task_id);
    w.key("attempt").value(r.attempt);
    w.end_object();
    return w.str() + "\n";
}

namespace {
template <class T>
T get(const YAML::Node& n, const char* key, T fallback) {
    try {
        if (n[key] && !n[key].IsNull()) return n[key].as<T>();
    } catch (const YAML::Exception&) {
    }
    return fallback;
}
}  // namespace

bool read_row_record(const fs::path& file, RowRecord& r) {
    std::error_code ec;
    if (!fs::is_regular_file(file, ec)) return false;
    YAML::Node n;
    try {
        n = YAML::LoadFile(file.string());
    } catch (const YAML::Exception&) {
        return false;
    }
    if (!n.IsMap()) return false;
    r.id = get<std::string>(n, "id", "");
    r.state = get<std::string>(n, "state", "");
    r.exit_code = get<int>(n, "exit_code", -1);
    r.signal = get<int>(n, "signal", 0);
    r.host = get<std::string>(n, "host", "");
    r.started_utc = get<std::string>(n, "started_utc", "");
    r.seconds = get<double>(n, "seconds", 0);
    r.peak_rss_bytes = get<long long>(n, "peak_rss_bytes", 0);
    r.job_id = get<std::string>(n, "slurm_job_id", "");
    r.array_job_id = get<std::string>(n, "slurm_array_job_id", "");
    r.array_task_id = get<std::string>(n, "slurm_array_task_id", "");
    r.attempt = get<int>(n, "attempt", 0);
    return true;
}

RowResult read_row_result(const fs::path& out_dir, const std::string& id) {
    RowResult res;
    res.id = id;
    const fs::path dir = out_dir / id;
    std::error_code ec;
    if (fs::exists(dir / kRowLog, ec)) res.log = (dir / kRowLog).string();
    RowRecord rec;
    const bool has_record = read_row_record(dir / kRowRecord, rec);
    if (has_record) {
        res.host = rec.host;
        res.job_id = rec.job_id;
        res.array_job_id = rec.array_job_id;
        res.array_task_id = rec.array_task_id;
        if (rec.state != "running") {
            res.exit_code = rec.state == "exited" ? rec.exit_code : -1;
            res.signal = rec.signal;
            res.seconds = rec.seconds;
            res.peak_rss_bytes = rec.peak_rss_bytes;
        }
    }
    std::string report_status;
    YAML::Node report;
    if (fs::is_regular_file(dir / "report.json", ec)) {
        try {
            report = YAML::LoadFile((dir / "report.json").string());
            report_status = get<std::string>(report, "status", "");
        } catch (const YAML::Exception&) {
        }
    }
    if (!report_status.empty()) {
        res.error = get<std::string>(report, "error", "");
        if (res.seconds < 0) res.seconds = get<double>(report, "wall_seconds", -1);
        const long long rss = get<long long>(report, "peak_rss_bytes", -1);
        if (rss > 0) res.peak_rss_bytes = rss;  // the run's own figure (the record's includes start-up)
        if (report["summary"] && report["summary"]["fracture"]) {
            res.fragments = get<long long>(report["summary"]["fracture"], "fragments", -1);
            res.steps = get<long long>(report["summary"]["fracture"], "bem_steps", -1);
        }
        if (!has_record || rec.state == "running") res.exit_code = report_status == "ok" ? 0 : res.exit_code;
    }
    // The status: the process's fate first (a row whose report says ok but whose process then
    // died is not trusted), then the report's.
    if (has_record && rec.state == "signalled") res.status = "failed";
    else if (res.exit_code == 2) res.status = "invalid";
    else if (res.exit_code == 130 || res.exit_code == 143 || report_status == "cancelled") res.status = "cancelled";
    else if (report_status == "ok" && (res.exit_code == 0 || res.exit_code == -1)) res.status = "ok";
    else if (report_status.empty() && res.exit_code < 0) res.status = "missing";
    else res.status = "failed";
    if (res.status == "failed" && res.error.empty()) {
        if (res.signal) res.error = "the process was killed by signal " + std::to_string(res.signal);
        else if (report_status.empty()) res.error = "no report.json (exit code " + std::to_string(res.exit_code) + ")";
    }
    if (res.status == "missing") res.error = has_record ? "no report.json: the attempt did not finish" : "not run";
    return res;
}

SummaryCounts count(const std::vector<RowResult>& rows) {
    SummaryCounts c;
    for (const auto& r : rows) {
        ++c.total;
        if (r.status == "ok") ++c.ok;
        else ++c.failed;
    }
    return c;
}

int batch_exit_code(const std::vector<RowResult>& rows) {
    bool invalid = false, failed = false;
    for (const auto& r : rows) {
        invalid = invalid || r.status == "invalid";
        failed = failed || r.status != "ok";
    }
    return invalid ? 2 : failed ? 1 : 0;
}

std::string summary_json(const std::vector<RowResult>& rows) {
    const SummaryCounts c = count(rows);
    graph::JsonWriter w;
    w.begin_object();
    w.key("rows").value(c.total);
    w.key("ok").value(c.ok);
    w.key("failed").value(c.failed);
    w.key("results").begin_array();
    for (const auto& r : rows) {
        w.begin_object();
        w.key("id").value(r.id);
        w.key("status").value(r.status);
        if (r.exit_code >= 0) w.key("exit_code").value(r.exit_code);
        else w.key("exit_code").null();
        if (r.signal) w.key("signal").value(r.signal);
        if (!r.error.empty()) w.key("error").value(r.error);
        if (r.fragments >= 0) w.key("fragments").value(r.fragments);
        else w.key("fragments").null();
        if (r.steps >= 0) w.key("steps").value(r.steps);
        else w.key("steps").null();
        if (r.seconds >= 0) w.key("seconds").value(r.seconds);
        else w.key("seconds").null();
        if (r.peak_rss_bytes >= 0) w.key("peak_rss_bytes").value(r.peak_rss_bytes);
        else w.key("peak_rss_bytes").null();
        w.key("host").value(r.host);
        w.key("slurm_job_id").value(r.job_id);
        w.key("slurm_array_job_id").value(r.array_job_id);
        w.key("slurm_array_task_id").value(r.array_task_id);
        w.key("log").value(r.log);
        w.end_object();
    }
    w.end_array();
    w.end_object();
    return w.str() + "\n";
}

namespace {
std::string csv_field(const std::string& s) {
    if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
    std::string q = "\"";
    for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
    return q + "\"";
}
std::string num(long long v) { return v >= 0 ? std::to_string(v) : ""; }
std::string num(double v) {
    if (v < 0) return "";
    char b[32];
    std::snprintf(b, sizeof b, "%.3f", v);
    return b;
}
}  // namespace

std::string summary_csv(const std::vector<RowResult>& rows) {
    std::string s = "id,status,exit_code,signal,fragments,steps,seconds,peak_rss_bytes,host,slurm_array_job_id,"
                    "slurm_array_task_id,slurm_job_id,error,log\n";
    for (const auto& r : rows) {
        s += csv_field(r.id) + "," + r.status + "," + num(static_cast<long long>(r.exit_code)) + "," +
             (r.signal ? std::to_string(r.signal) : "") + "," + num(r.fragments) + "," + num(r.steps) + "," + num(r.seconds) +
             "," + num(r.peak_rss_bytes) + "," + csv_field(r.host) + "," + csv_field(r.array_job_id) + "," +
             csv_field(r.array_task_id) + "," + csv_field(r.job_id) + "," + csv_field(r.error) + "," + csv_field(r.log) + "\n";
    }
    return s;
}

fs::path row_list_file(const fs::path& out_dir) { return out_dir / ".batch" / "rows.txt"; }

void write_row_list(const fs::path& out_dir, const std::vector<std::string>& ids) {
    graph::write_atomically(row_list_file(out_dir), [&](std::ostream& o) {
        for (const auto& id : ids) o << id << "\n";
    });
}

std::vector<std::string> read_row_list(const fs::path& out_dir) {
    std::ifstream in(row_list_file(out_dir));
    if (!in)
        throw std::runtime_error(out_dir.string() + " is not a batch output directory (no " + row_list_file(out_dir).string() +
                                 "; run `crackflow batch MANIFEST --out " + out_dir.string() + "` first)");
    std::vector<std::string> ids;
    std::string line;
    while (std::getline(in, line))
        if (!line.empty()) ids.push_back(line);
    return ids;
}

std::vector<RowResult> collect(const fs::path& out_dir) {
    std::vector<RowResult> rows;
    for (const auto& id : read_row_list(out_dir)) rows.push_back(read_row_result(out_dir, id));
    graph::write_atomically(out_dir / "summary.json", [&](std::ostream& o) { o << summary_json(rows); });
    graph::write_atomically(out_dir / "summary.csv", [&](std::ostream& o) { o << summary_csv(rows); });
    return rows;
}

}  // namespace cf::runtime::batch
