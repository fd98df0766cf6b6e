#pragma once
// Batch manifests: one row per independent pipeline run, as CSV or YAML (docs/batch.md).
//
//   CSV:  id,pipeline,bunny.path,material.E
//         bunny_soft,fracture.yaml,data/meshes/bunny00.off,1e9
//   YAML: defaults: {pipeline: fracture.yaml}          # optional, applied to every row
//         rows:
//           - {id: bunny_soft, bunny.path: data/meshes/bunny00.off, material.E: 1e9}
//
// Columns: `id` (the row's output folder DIR/<id>), `pipeline` (relative to the manifest's folder)
// and `NODE.PARAM` overrides, whose cells are YAML values like `--set` takes them; an empty cell
// leaves the pipeline's value. Parsing is plain text handling with locations; checking the rows
// against their pipelines is batch_validation.
#include <string>
#include <vector>

namespace cf::runtime::batch {

// A problem found in a manifest, located by manifest line and character column (both 1-based;
// 0 = unknown), with the row and column names when it concerns one cell.
struct Problem {
    std::string file;
    int line = 0, column = 0;
    std::string row_id;       // "" when not about a row
    std::string column_name;  // "" when not about a column
    std::string message;
    std::string hint;
};
std::string format(const Problem& p);  // FILE:LINE:COL: error: row 'id', column 'c': message (+ hint line)

struct Cell {
    std::string column;  // NODE.PARAM
    std::string value;   // YAML text
    int line = 0, column_number = 0;
};

struct Row {
    int number = 0;        // 1-based data row (the header is not a row)
    int line = 0;          // manifest line where the row starts
    std::string id;
    int id_column = 0;     // character column of the id cell
    std::string pipeline;  // absolute path (relative paths are taken from the manifest's folder)
    std::string pipeline_text;  // as written
    int pipeline_line = 0, pipeline_column = 0;
    std::vector<Cell> overrides;  // non-empty NODE.PARAM cells, in column order
};

struct ColumnHeader {
    std::string name;
    int line = 0, column = 0;
};

struct Manifest {
    std::string file;
    std::vector<ColumnHeader> columns;  // as declared (CSV header; YAML: every key met, first place)
    std::vector<Row> rows;
};

// Reads a manifest file (.csv, or .yaml/.yml). Every problem of the text is appended to
// `problems`: malformed CSV/YAML, unknown columns, missing or duplicate or unusable ids, a
// missing pipeline, a pipeline file that does not exist. Rows with problems are still returned
// when they have an id, so that the pipelines of the others can be checked too.
Manifest read_manifest(const std::string& path, std::vector<Problem>& problems);
Manifest parse_manifest_csv(const std::string& text, const std::string& file, std::vector<Problem>& problems);
Manifest parse_manifest_yaml(const std::string& text, const std::string& file, std::vector<Problem>& problems);

// "a.b=c" texts for `crackflow run --set`, in column order.
std::vector<std::string> set_arguments(const Row& row);

}  // namespace cf::runtime::batch
