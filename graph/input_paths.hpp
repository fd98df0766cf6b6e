#pragma once
// Input files named by parameters (ParamDecl::reads_file, e.g. import.mesh's path). An absolute
// path is used as given. A relative one is looked up, in this order, in
//   1. the directory of the file that gives the value (the pipeline file, or the sub-pipeline
//      file; the working directory for a --set or batch manifest value),
//   2. each directory of the environment variable CRACKFLOW_DATA_PATH (':'-separated),
//   3. the build's data directory (CRACKFLOW_DATA_DIR, compiled in: CMake extracts libcgal-demo's
//      meshes there as meshes/*.off),
// and the first that exists is used, as an absolute path. So a pipeline runs from any working
// directory, and shared data lives in one place.
#include <filesystem>
#include <string>
#include <vector>

namespace cf::graph {

inline constexpr const char* kDataPathVariable = "CRACKFLOW_DATA_PATH";
// Sub-pipeline files (`use: FILE`) are looked up the same way: beside the using file, then in each
// directory of CRACKFLOW_PIPELINE_PATH (':'-separated), then in crackflow's own pipelines directory
// (CRACKFLOW_PIPELINE_DIR, compiled in), so a pipeline anywhere can say `use: lib/fracture.yaml`.
inline constexpr const char* kPipelinePathVariable = "CRACKFLOW_PIPELINE_PATH";

struct InputFileSearch {
    std::string found;               // absolute, normalised; empty when none exists
    std::vector<std::string> tried;  // every absolute path looked at, in order
};

// The directories of steps 2 and 3 above, in order.
std::vector<std::filesystem::path> data_search_path();

InputFileSearch find_input_file(const std::string& value, const std::filesystem::path& base_dir);

// The directories searched after the using file's own for a sub-pipeline, in order.
std::vector<std::filesystem::path> pipeline_search_path();

InputFileSearch find_pipeline_file(const std::string& value, const std::filesystem::path& base_dir);

}  // namespace cf::graph
