// Batch scheduling and results without processes: rows per task, packing, array splitting at
// MaxArraySize, completion from report.json, the summary of rows, the Slurm job script.
#include "runtime/batch_plan.hpp"
#include "runtime/batch_slurm.hpp"
#include "runtime/batch_summary.hpp"
#include "tests/harness/node_harness.hpp"

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <fstream>

namespace cf::runtime::batch {
namespace {

namespace fs = std::filesystem;

TEST(BatchPlan, RowsPerTaskKeepTheOverheadBelowFivePercent) {
    // overhead / (R * row) <= 0.05  <=>  R >= overhead / (0.05 row): by hand, 1 s / (0.05 * 2 s) = 10.
    EXPECT_EQ(rows_per_task(2.0, 1.0), 10);
    EXPECT_EQ(rows_per_task(3.0, 1.0), 7);   // 6.67 -> 7: 1 / 21 = 4.8 %
    EXPECT_EQ(rows_per_task(20.0, 1.0), 1);  // exactly 5 %
    EXPECT_EQ(rows_per_task(60.0, 1.0), 1);
    EXPECT_EQ(rows_per_task(0.7, 0.7), 20);
    for (double row : {0.1, 0.5, 1.3, 7.0, 19.0}) {
        const int r = rows_per_task(row, 0.7);
        EXPECT_LE(0.7 / (r * row), 0.05 + 1e-12) << row;
        if (r > 1) {
            EXPECT_GT(0.7 / ((r - 1) * row), 0.05) << row;  // and no more rows than needed
        }
    }
    EXPECT_EQ(rows_per_task(0.0, 1.0), 1);  // unknown duration: one row per task
}

TEST(BatchPlan, PackingIsFixedByRowsPerTaskAndRetriesResubmitOnlyTasksWithPendingRows) {
    const auto tasks = pack_rows(10, 3);
    ASSERT_EQ(tasks.size(), 4u);
    EXPECT_EQ(tasks[0], (std::vector<std::size_t>{0, 1, 2}));
    EXPECT_EQ(tasks[3], (std::vector<std::size_t>{9}));
    std::vector<bool> complete(10, true);
    EXPECT_TRUE(tasks_with_pending_rows(tasks, complete).empty());
    complete[4] = false;
    complete[9] = false;
    EXPECT_EQ(tasks_with_pending_rows(tasks, complete), (std::vector<long>{1, 3}));
}

TEST(BatchPlan, ArraysSplitAtMaxArraySize) {
    std::vector<long> all(2500);
    for (long i = 0; i < 2500; ++i) all[i] = i;
    const auto chunks = split_into_arrays(all, 1001, 8);
    ASSERT_EQ(chunks.size(), 3u);
    EXPECT_EQ(chunks[0].offset, 0);
    EXPECT_EQ(chunks[0].array_spec, "0-1000%8");
    EXPECT_EQ(chunks[1].offset, 1001);
    EXPECT_EQ(chunks[1].array_spec, "0-1000%8");
    EXPECT_EQ(chunks[2].offset, 2002);
    EXPECT_EQ(chunks[2].array_spec, "0-497%8");
    std::size_t n = 0;
    for (const auto& c : chunks) {
        n += c.indices.size();
        for (long i : c.indices) EXPECT_LT(i, 1001);
    }
    EXPECT_EQ(n, 2500u);
    // A retry of tasks 3, 4, 5 and 1500 with no limit on running tasks.
    const auto retry = split_into_arrays({3, 4, 5, 1500}, 1001, 0);
    ASSERT_EQ(retry.size(), 2u);
    EXPECT_EQ(retry[0].array_spec, "3-5");
    EXPECT_EQ(retry[1].offset, 1001);
    EXPECT_EQ(retry[1].array_spec, "499");
    EXPECT_EQ(index_ranges({0, 2, 3, 4, 7, 9, 10}), "0,2-4,7,9-10");
}

TEST(BatchPlan, MaxArraySizeFromScontrol) {
    EXPECT_EQ(parse_max_array_size("MailProg                = /bin/true\nMaxArraySize            = 4\nMaxJobCount = 10000\n"), 4);
    EXPECT_EQ(parse_max_array_size("MaxJobCount = 10000\n"), 1001);
    EXPECT_EQ(parse_max_array_size(""), 1001);
}

Row row_of(const std::string& id) {
    Row r;
    r.id = id;
    r.pipeline = "/p/pipe.yaml";
    r.overrides = {{"a.b", "1e9", 2, 3}};
    return r;
}

void write(const fs::path& f, const std::string& text) {
    fs::create_directories(f.parent_path());
    std::ofstream(f) << text;
}

TEST(BatchPlan, ARowIsCompleteOnlyWithAnOkReportOfTheSameParameters) {
    const fs::path dir = cf::testing::temp_dir("completion");
    const Row row = row_of("r");
    EXPECT_EQ(row_completion(dir / "r", row, true), "missing");
    write(dir / "r/report.json", R"({"pipeline":"/p/pipe.yaml","status":"ok","fast":true,"overrides":["a.b=1e9"]})");
    EXPECT_EQ(row_completion(dir / "r", row, true), "ok");
    EXPECT_EQ(row_completion(dir / "r", row, false), "stale");  // asked for the full run now
    Row changed = row;
    changed.overrides[0].value = "2e9";
    EXPECT_EQ(row_completion(dir / "r", changed, true), "stale");
    write(dir / "r/report.json", R"({"pipeline":"/p/pipe.yaml","status":"failed","fast":true,"overrides":["a.b=1e9"]})");
    EXPECT_EQ(row_completion(dir / "r", row, true), "failed");
    write(dir / "r/report.json", R"({"pipeline":"/p/pipe.yaml","status":"cancelled","fast":true,"overrides":["a.b=1e9"]})");
    EXPECT_EQ(row_completion(dir / "r", row, true), "cancelled");
    write(dir / "r/report.json", R"({"pipeline":)");
    EXPECT_EQ(row_completion(dir / "r", row, true), "unreadable");
}

TEST(BatchSummary, StatusFromTheProcessAndTheReport) {
    const fs::path dir = cf::testing::temp_dir("summary");
    // ok: report ok, exit 0, with the fracture figures and the Slurm ids of the record.
    RowRecord rec;
    rec.id = "ok";
    rec.state = "exited";
    rec.exit_code = 0;
    rec.host = "node7";
    rec.seconds = 2.5;
    rec.peak_rss_bytes = 1000;
    rec.array_job_id = "41";
    rec.array_task_id = "3";
    rec.job_id = "44";
    write(dir / "ok" / kRowRecord, row_record_json(rec));
    write(dir / "ok/report.json",
          R"({"status":"ok","wall_seconds":2.0,"peak_rss_bytes":5000,"summary":{"fracture":{"bem_steps":4,"fragments":2}}})");
    // killed: the process died of SIGKILL; no report.
    rec.id = "killed";
    rec.state = "signalled";
    rec.exit_code = -1;
    rec.signal = 9;
    write(dir / "killed" / kRowRecord, row_record_json(rec));
    write(dir / "killed" / kRowLog, "log\n");
    // failed: exit 1 with the report's error.
    rec.id = "failed";
    rec.state = "exited";
    rec.exit_code = 1;
    rec.signal = 0;
    write(dir / "failed" / kRowRecord, row_record_json(rec));
    write(dir / "failed/report.json", R"({"status":"failed","error":"node 'box': cannot open mesh file"})");
    // invalid: exit 2.
    rec.id = "invalid";
    rec.exit_code = 2;
    write(dir / "invalid" / kRowRecord, row_record_json(rec));
    // running: the attempt started and never finished (a lost node).
    rec.id = "lost";
    rec.state = "running";
    write(dir / "lost" / kRowRecord, row_record_json(rec));
    write_row_list(dir, {"ok", "killed", "failed", "invalid", "lost", "never"});

    const auto rows = collect(dir);
    ASSERT_EQ(rows.size(), 6u);
    EXPECT_EQ(rows[0].status, "ok");
    EXPECT_EQ(rows[0].exit_code, 0);
    EXPECT_EQ(rows[0].fragments, 2);
    EXPECT_EQ(rows[0].steps, 4);
    EXPECT_DOUBLE_EQ(rows[0].seconds, 2.5);
    EXPECT_EQ(rows[0].peak_rss_bytes, 5000);
    EXPECT_EQ(rows[0].host, "node7");
    EXPECT_EQ(rows[0].array_job_id, "41");
    EXPECT_EQ(rows[0].array_task_id, "3");
    EXPECT_EQ(rows[1].status, "failed");
    EXPECT_EQ(rows[1].signal, 9);
    EXPECT_EQ(rows[1].error, "the process was killed by signal 9");
    EXPECT_EQ(rows[1].log, (dir / "killed" / kRowLog).string());
    EXPECT_EQ(rows[2].status, "failed");
    EXPECT_EQ(rows[2].error, "node 'box': cannot open mesh file");
    EXPECT_EQ(rows[3].status, "invalid");
    EXPECT_EQ(rows[4].status, "missing");
    EXPECT_EQ(rows[5].status, "missing");
    EXPECT_EQ(rows[5].error, "not run");
    const SummaryCounts n = count(rows);
    EXPECT_EQ(n.total, 6);
    EXPECT_EQ(n.ok, 1);
    EXPECT_EQ(n.failed, 5);  // rows without a report count as failed
    // One exit code for every backend and --collect: an invalid row (bad input) makes it 2, else
    // any row not ok 1, else 0.
    EXPECT_EQ(batch_exit_code(rows), 2);
    std::vector<RowResult> without_invalid = rows;
    without_invalid.erase(without_invalid.begin() + 3);
    EXPECT_EQ(batch_exit_code(without_invalid), 1);
    EXPECT_EQ(batch_exit_code({rows[0]}), 0);
    EXPECT_EQ(batch_exit_code({}), 0);

    const YAML::Node s = YAML::LoadFile((dir / "summary.json").string());
    EXPECT_EQ(s["ok"].as<int>(), 1);
    EXPECT_EQ(s["failed"].as<int>(), 5);
    EXPECT_EQ(s["results"][0]["fragments"].as<int>(), 2);
    EXPECT_TRUE(s["results"][5]["exit_code"].IsNull());
    std::ifstream csv(dir / "summary.csv");
    std::string header, first, second;
    std::getline(csv, header), std::getline(csv, first), std::getline(csv, second);
    EXPECT_EQ(header, "id,status,exit_code,signal,fragments,steps,seconds,peak_rss_bytes,host,slurm_array_job_id,"
                      "slurm_array_task_id,slurm_job_id,error,log");
    EXPECT_EQ(first, "ok,ok,0,,2,4,2.500,5000,node7,41,3,44,,");
    EXPECT_EQ(second.substr(0, 26), "killed,failed,,9,,,2.500,1");
}

TEST(BatchSlurm, JobScriptRunsTheTaskOfArrayIndexPlusOffset) {
    JobScript s;
    s.exe = "/opt/crackflow";
    s.manifest = "/shared/m.csv";
    s.out_dir = "/shared/out";
    s.workdir = "/shared";
    s.tasks_file = "/shared/out/.batch/slurm/x/tasks.txt";
    s.log_dir = "/shared/out/.batch/slurm/x";
    s.job_name = "crackflow-out";
    s.fast = true;
    s.slurm.partition = "short";
    s.slurm.time = "0:30:00";
    s.slurm.mem = "4G";
    s.slurm.cpus_per_task = 2;
    const std::string t = job_script(s);
    for (const char* line : {"#!/bin/sh\n", "#SBATCH --output=/shared/out/.batch/slurm/x/task_%A_%a.log\n",
                             "#SBATCH --open-mode=append\n", "#SBATCH --chdir=/shared\n", "#SBATCH --cpus-per-task=2\n",
                             "#SBATCH --mem=4G\n", "#SBATCH --time=0:30:00\n", "#SBATCH --partition=short\n",
                             "exec /opt/crackflow batch /shared/m.csv --out /shared/out --task-file "
                             "/shared/out/.batch/slurm/x/tasks.txt --fast --threads 2 --task \"$(( ${1:-0} + "
                             "SLURM_ARRAY_TASK_ID ))\"\n"})
        EXPECT_NE(t.find(line), std::string::npos) << line << "\nin\n" << t;
}

}  // namespace
}  // namespace cf::runtime::batch

namespace cf::runtime::batch {
namespace {

TEST(BatchSlurm, ConfigFileGivesDefaultsTheCommandLineOverrides) {
    const fs::path dir = cf::testing::temp_dir("slurm-config");
    write(dir / "c.yaml", "partition: short\ntime: \"0:30:00\"\nmem: 4G\ncpus-per-task: 2\nsbatch-options: [--account=vfx]\n");
    SlurmOptions o;
    o.mem = "8G";  // given on the command line
    apply_slurm_config((dir / "c.yaml").string(), {"mem"}, o);
    EXPECT_EQ(o.partition, "short");
    EXPECT_EQ(o.time, "0:30:00");
    EXPECT_EQ(o.mem, "8G");
    EXPECT_EQ(o.cpus_per_task, 2);
    EXPECT_EQ(o.sbatch_options, std::vector<std::string>{"--account=vfx"});
    write(dir / "bad.yaml", "partition: short\ncpus_per_task: 2\n");
    try {
        apply_slurm_config((dir / "bad.yaml").string(), {}, o);
        ADD_FAILURE() << "an unknown key was accepted";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("bad.yaml:2:1: unknown key 'cpus_per_task' (did you mean 'cpus-per-task'?)"),
                  std::string::npos)
            << e.what();
    }
    write(dir / "neg.yaml", "max-parallel: 0\n");
    EXPECT_THROW(apply_slurm_config((dir / "neg.yaml").string(), {}, o), std::runtime_error);
}

}  // namespace
}  // namespace cf::runtime::batch
