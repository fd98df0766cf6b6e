#include "runtime/batch_validation.hpp"

#include "graph/diagnostics.hpp"
#include "graph/pipeline.hpp"

#include <map>
#include <set>

namespace cf::runtime::batch {

void validate_manifest(const Manifest& manifest, const graph::NodeRegistry& registry, bool fast,
                       std::vector<Problem>& problems) {
    // Each pipeline once on its own: its own mistakes are reported once, not once per row.
    std::map<std::string, bool> pipeline_ok;
    std::map<std::string, std::set<std::string>> node_names;  // per good pipeline
    std::map<std::string, std::string> first_row;
    for (const Row& row : manifest.rows) {
        if (row.pipeline.empty() || pipeline_ok.count(row.pipeline)) continue;
        first_row[row.pipeline] = row.id;
        std::vector<graph::Diagnostic> diags;
        graph::LoadOptions options;
        options.fast = fast;
        options.require_input_files = false;  // a row's data may appear before it runs (the run checks it)
        const graph::Plan plan = graph::load_pipeline_file(row.pipeline, registry, options, diags);
        pipeline_ok[row.pipeline] = diags.empty();
        for (const auto& d : diags)
            problems.push_back({d.loc.file, d.loc.line, d.loc.column, "", "",
                                d.message + " (in the pipeline of row '" + row.id + "', manifest line " +
                                    std::to_string(row.pipeline_line) + (fast ? ", as run --fast applies it" : "") + ")",
                                d.hint});
        for (const auto& n : plan.nodes) node_names[row.pipeline].insert(n.name);
        for (const auto& u : plan.uses) node_names[row.pipeline].insert(u.name);  // `fracture.method` sets a sub-pipeline's parameter
    }

    // A column whose node is in none of the manifest's pipelines is an unknown column, whichever
    // rows leave it empty.
    std::set<std::string> bad_columns;
    if (!node_names.empty())
        for (const ColumnHeader& c : manifest.columns) {
            if (c.name == "id" || c.name == "pipeline") continue;
            const std::string node = c.name.substr(0, c.name.find('.'));
            std::vector<std::string> all;
            bool found = false;
            for (const auto& [p, names] : node_names) {
                found = found || names.count(node) > 0;
                all.insert(all.end(), names.begin(), names.end());
            }
            if (found) continue;
            bad_columns.insert(c.name);
            problems.push_back({manifest.file, c.line, c.column, "", c.name,
                                "unknown column: no pipeline of this manifest has a node '" + node + "'",
                                graph::did_you_mean(node, all)});
        }

    for (const Row& row : manifest.rows) {
        auto ok = pipeline_ok.find(row.pipeline);
        if (ok == pipeline_ok.end() || !ok->second) continue;
        graph::LoadOptions options;
        options.fast = fast;
        options.require_input_files = false;  // a row's data may appear before it runs (the run checks it)
        for (const Cell& cell : row.overrides) {
            if (bad_columns.count(cell.column)) continue;
            const auto dot = cell.column.find('.');
            options.overrides.push_back({cell.column.substr(0, dot), cell.column.substr(dot + 1), cell.value,
                                         {manifest.file, cell.line, cell.column_number}});
        }
        std::vector<graph::Diagnostic> diags;
        graph::load_pipeline_file(row.pipeline, registry, options, diags);
        for (const auto& d : diags) {
            Problem p{d.loc.file, d.loc.line, d.loc.column, row.id, "", d.message, d.hint};
            if (d.loc.file == manifest.file) {
                for (const Cell& cell : row.overrides)
                    if (cell.line == d.loc.line && cell.column_number == d.loc.column) p.column_name = cell.column;
            } else {
                // A problem the overrides caused elsewhere (e.g. a type no longer matching): say where the row is.
                p.message += " (with the overrides of manifest " + manifest.file + ":" + std::to_string(row.line) + ")";
            }
            problems.push_back(std::move(p));
        }
    }
}

}  // namespace cf::runtime::batch
