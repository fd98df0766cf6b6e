#include "runtime/batch_manifest.hpp"

#include "graph/diagnostics.hpp"

#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <cctype>
#include <fstream>
#include <map>
#include <sstream>

namespace cf::runtime::batch {

namespace fs = std::filesystem;

std::string format(const Problem& p) {
    std::string s = p.file.empty() ? std::string("<manifest>") : p.file;
    if (p.line > 0) s += ":" + std::to_string(p.line) + ":" + std::to_string(p.column);
    s += ": error: ";
    if (!p.row_id.empty()) s += "row '" + p.row_id + "'" + (p.column_name.empty() ? ": " : ", ");
    if (!p.column_name.empty()) s += "column '" + p.column_name + "': ";
    s += p.message;
    if (!p.hint.empty()) s += "\n  hint: " + p.hint;
    return s;
}

namespace {

bool is_word(const std::string& s) {
    if (s.empty()) return false;
    for (char c : s)
        if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
    return true;
}

// A node's name: words joined by '/' inside sub-pipelines (fracture/propagate).
bool is_node_path(const std::string& s) {
    std::size_t start = 0;
    for (std::size_t slash; (slash = s.find('/', start)) != std::string::npos; start = slash + 1)
        if (!is_word(s.substr(start, slash - start))) return false;
    return is_word(s.substr(start));
}

// NODE.PARAM, with names as pipelines allow them.
bool is_override_column(const std::string& name) {
    const auto dot = name.find('.');
    return dot != std::string::npos && is_node_path(name.substr(0, dot)) && is_word(name.substr(dot + 1));
}

// An id names a folder under --out, so it must be a plain, portable file name.
std::string id_problem(const std::string& id) {
    if (id.empty()) return "the id is empty";
    if (id.size() > 100) return "the id is longer than 100 characters";
    if (id[0] == '.' || id[0] == '-') return "the id '" + id + "' starts with '" + id.substr(0, 1) + "'";
    for (char c : id)
        if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.'))
            return "the id '" + id + "' holds the character '" + std::string(1, c) + "'";
    if (id == "summary.json" || id == "summary.csv") return "the id '" + id + "' is the name of the batch summary";
    return "";
}
const char* kIdHint = "ids name the output folders DIR/<id>: use letters, digits, '_', '-' and '.', not first '.' or '-'";

struct Field {
    std::string text;
    int line = 0, column = 0;
};

// RFC 4180 records with locations: quoted fields may hold commas, doubled quotes and line breaks.
// Lines starting with '#' between records and blank lines are skipped.
std::vector<std::vector<Field>> csv_records(const std::string& text, const std::string& file,
                                            std::vector<Problem>& problems) {
    std::vector<std::vector<Field>> records;
    std::size_t i = 0;
    int line = 1, col = 1;
    if (text.compare(0, 3, "\xEF\xBB\xBF") == 0) i = 3;  // a spreadsheet's UTF-8 byte-order mark
    auto advance = [&](char c) {
        if (c == '\n') ++line, col = 1;
        else ++col;
    };
    while (i < text.size()) {
        // Start of a record: skip comments and blank lines.
        if (text[i] == '#' || text[i] == '\n' || (text[i] == '\r' && i + 1 < text.size() && text[i + 1] == '\n')) {
            while (i < text.size() && text[i] != '\n') advance(text[i++]);
            if (i < text.size()) advance(text[i++]);
            continue;
        }
        std::vector<Field> record;
        bool end_of_record = false;
        while (!end_of_record) {
            Field f;
            f.line = line, f.column = col;
            if (i < text.size() && text[i] == '"') {
                const int qline = line, qcol = col;
                advance(text[i++]);
                bool closed = false;
                while (i < text.size()) {
                    if (text[i] == '"') {
                        if (i + 1 < text.size() && text[i + 1] == '"') {
                            f.text += '"';
                            advance(text[i++]), advance(text[i++]);
                            continue;
                        }
                        advance(text[i++]);
                        closed = true;
                        break;
                    }
                    f.text += text[i];
                    advance(text[i++]);
                }
                if (!closed) {
                    problems.push_back({file, qline, qcol, "", "", "a quoted field is not closed",
                                        "end it with '\"' (write a quote inside a quoted field as '\"\"')"});
                    return records;
                }
                // Only a separator or the end of the line may follow the closing quote.
                if (i < text.size() && text[i] != ',' && text[i] != '\n' && text[i] != '\r') {
                    problems.push_back({file, line, col, "", "", "text after a closing quote",
                                        "quote the whole field: \"...\""});
                    while (i < text.size() && text[i] != ',' && text[i] != '\n') advance(text[i++]);
                }
            } else {
                while (i < text.size() && text[i] != ',' && text[i] != '\n') {
                    if (text[i] != '\r') f.text += text[i];
                    advance(text[i++]);
                }
                // Spaces around an unquoted field are layout, not content.
                const auto b = f.text.find_first_not_of(" \t");
                const auto e = f.text.find_last_not_of(" \t");
                if (b == std::string::npos) f.text.clear();
                else {
                    f.column += static_cast<int>(b);
                    f.text = f.text.substr(b, e - b + 1);
                }
            }
            if (i < text.size() && text[i] == '\r') advance(text[i++]);
            record.push_back(std::move(f));
            if (i >= text.size()) end_of_record = true;
            else if (text[i] == ',') advance(text[i++]);
            else if (text[i] == '\n') advance(text[i++]), end_of_record = true;
        }
        records.push_back(std::move(record));
    }
    return records;
}

// A CSV cell is YAML like a --set value (1e9, [0, 0, 1], true); text that YAML would read as a
// mapping or not at all (a boundary-condition string such as "top: traction 0 0 1e6; *: ...") is
// meant as a string, since no parameter takes a mapping: it is quoted for the loader.
std::string cell_yaml(const std::string& text) {
    try {
        const YAML::Node n = YAML::Load(text);
        if (!n.IsMap()) return text;
    } catch (const YAML::Exception&) {
    }
    YAML::Emitter e;
    e << YAML::DoubleQuoted << text;
    return e.c_str();
}

// The checks shared by both formats once the cells of a row are known.
class RowChecker {
public:
    RowChecker(Manifest& m, std::vector<Problem>& problems) : m_(m), problems_(problems) {
        base_ = fs::absolute(fs::path(m.file)).parent_path();
    }
    void add(Row row, bool has_id, bool has_pipeline) {
        if (!has_id) {
            problems_.push_back({m_.file, row.line, 1, "", "", "row " + std::to_string(row.number) + " has no 'id'",
                                 kIdHint});
            return;
        }
        if (auto p = id_problem(row.id); !p.empty()) {
            problems_.push_back({m_.file, row.line, row.id_column, row.id, "id", p, kIdHint});
            return;
        }
        if (auto it = first_line_.find(row.id); it != first_line_.end()) {
            problems_.push_back({m_.file, row.line, row.id_column, row.id, "id",
                                 "duplicate id: row " + std::to_string(row.number) + " repeats the id of line " +
                                     std::to_string(it->second),
                                 "every row writes DIR/<id>, so ids must be unique"});
            return;
        }
        first_line_[row.id] = row.line;
        if (!has_pipeline || row.pipeline_text.empty()) {
            problems_.push_back({m_.file, row.pipeline_line ? row.pipeline_line : row.line,
                                 row.pipeline_line ? row.pipeline_column : row.id_column, row.id, "pipeline",
                                 "no pipeline file", "name the pipeline YAML file, relative to the manifest's folder"});
        } else {
            fs::path p(row.pipeline_text);
            if (p.is_relative()) p = base_ / p;
            p = p.lexically_normal();
            std::error_code ec;
            if (!fs::is_regular_file(p, ec)) {
                problems_.push_back({m_.file, row.pipeline_line, row.pipeline_column, row.id, "pipeline",
                                     "unknown pipeline: the file " + p.string() + " does not exist",
                                     "relative pipeline paths are taken from the manifest's folder " + base_.string()});
                row.pipeline.clear();
            } else {
                row.pipeline = p.string();
            }
        }
        m_.rows.push_back(std::move(row));
    }

private:
    Manifest& m_;
    std::vector<Problem>& problems_;
    fs::path base_;
    std::map<std::string, int> first_line_;
};

bool check_column_name(const std::string& name, const std::string& file, int line, int column,
                       std::vector<Problem>& problems) {
    if (name == "id" || name == "pipeline" || is_override_column(name)) return true;
    std::string lower;
    for (char c : name) lower += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    std::string hint = lower == "id" || lower == "pipeline" ? lower : graph::closest_match(name, {"id", "pipeline"});
    problems.push_back({file, line, column, "", name, "unknown column",
                        hint.empty() ? "columns are 'id', 'pipeline' and overrides NODE.PARAM (e.g. bunny.path)"
                                     : "did you mean '" + hint + "'?"});
    return false;
}

}  // namespace

Manifest parse_manifest_csv(const std::string& text, const std::string& file, std::vector<Problem>& problems) {
    Manifest m;
    m.file = file;
    const auto records = csv_records(text, file, problems);
    if (records.empty()) {
        problems.push_back({file, 1, 1, "", "", "the manifest has no header line",
                            "the first line names the columns: id,pipeline,NODE.PARAM,..."});
        return m;
    }
    const auto& header = records.front();
    std::vector<bool> usable(header.size(), false);
    int id_col = -1, pipeline_col = -1;
    std::map<std::string, int> seen;
    for (std::size_t c = 0; c < header.size(); ++c) {
        const Field& h = header[c];
        if (h.text.empty()) {
            problems.push_back({file, h.line, h.column, "", "", "column " + std::to_string(c + 1) + " has no name",
                                "name every column: id, pipeline or NODE.PARAM"});
            continue;
        }
        if (auto it = seen.find(h.text); it != seen.end()) {
            problems.push_back({file, h.line, h.column, "", h.text,
                                "the column appears twice (also column " + std::to_string(it->second) + ")",
                                "keep one column per name"});
            continue;
        }
        seen[h.text] = static_cast<int>(c + 1);
        if (!check_column_name(h.text, file, h.line, h.column, problems)) continue;
        usable[c] = true;
        m.columns.push_back({h.text, h.line, h.column});
        if (h.text == "id") id_col = static_cast<int>(c);
        if (h.text == "pipeline") pipeline_col = static_cast<int>(c);
    }
    if (id_col < 0)
        problems.push_back({file, header.front().line, 1, "", "", "the header has no 'id' column",
                            "add a column 'id': each row's output folder name"});
    if (pipeline_col < 0)
        problems.push_back({file, header.front().line, 1, "", "", "the header has no 'pipeline' column",
                            "add a column 'pipeline': each row's pipeline file"});
    RowChecker checker(m, problems);
    for (std::size_t r = 1; r < records.size(); ++r) {
        const auto& rec = records[r];
        Row row;
        row.number = static_cast<int>(r);
        row.line = rec.front().line;
        if (rec.size() != header.size()) {
            problems.push_back({file, row.line, rec.back().column, "", "",
                                "row " + std::to_string(r) + " has " + std::to_string(rec.size()) + " fields, the header " +
                                    std::to_string(header.size()),
                                "give every row one field per column (empty for the pipeline's value); quote fields "
                                "holding commas"});
            continue;
        }
        for (std::size_t c = 0; c < rec.size(); ++c) {
            if (!usable[c]) continue;
            const Field& f = rec[c];
            const std::string& name = header[c].text;
            if (static_cast<int>(c) == id_col) row.id = f.text, row.id_column = f.column;
            else if (static_cast<int>(c) == pipeline_col)
                row.pipeline_text = f.text, row.pipeline_line = f.line, row.pipeline_column = f.column;
            else if (!f.text.empty())
                row.overrides.push_back({name, cell_yaml(f.text), f.line, f.column});
        }
        if (id_col >= 0 && row.id.empty()) {
            problems.push_back({file, row.line, rec[id_col].column, "", "id", "row " + std::to_string(r) + " has an empty id",
                                kIdHint});
            continue;
        }
        checker.add(std::move(row), id_col >= 0, pipeline_col >= 0);
    }
    if (records.size() == 1)
        problems.push_back({file, header.front().line, 1, "", "", "the manifest has a header but no rows", ""});
    return m;
}

Manifest parse_manifest_yaml(const std::string& text, const std::string& file, std::vector<Problem>& problems) {
    Manifest m;
    m.file = file;
    YAML::Node root;
    try {
        root = YAML::Load(text);
    } catch (const YAML::ParserException& e) {
        problems.push_back({file, e.mark.line + 1, e.mark.column + 1, "", "", "YAML syntax error: " + e.msg,
                            "check indentation and that every 'key: value' has a space after the colon"});
        return m;
    }
    auto where = [](const YAML::Node& n) {
        const YAML::Mark k = n.Mark();
        return std::pair<int, int>{k.line >= 0 ? k.line + 1 : 0, k.column >= 0 ? k.column + 1 : 0};
    };
    if (!root.IsMap()) {
        problems.push_back({file, 1, 1, "", "", "a YAML manifest is a mapping with a 'rows:' list",
                            "rows:\n    - {id: a, pipeline: p.yaml, node.param: value}"});
        return m;
    }
    YAML::Node rows, defaults;
    bool has_rows = false, has_defaults = false;
    for (auto it = root.begin(); it != root.end(); ++it) {
        const std::string key = it->first.Scalar();
        auto [l, c] = where(it->first);
        if (key == "rows") rows = it->second, has_rows = true;
        else if (key == "defaults") defaults = it->second, has_defaults = true;
        else if (key != "description")
            problems.push_back({file, l, c, "", "", "unknown top-level key '" + key + "'",
                                graph::did_you_mean(key, {"rows", "defaults", "description"})});
    }
    if (!has_rows || !rows.IsSequence() || rows.size() == 0) {
        auto [l, c] = has_rows ? where(rows) : std::pair<int, int>{1, 1};
        problems.push_back({file, l, c, "", "", "the manifest has no rows", "rows:\n    - {id: a, pipeline: p.yaml}"});
        return m;
    }
    if (has_defaults && !defaults.IsMap()) {
        auto [l, c] = where(defaults);
        problems.push_back({file, l, c, "", "", "'defaults:' must be a mapping of column: value", ""});
        has_defaults = false;
    }
    std::map<std::string, bool> column_ok;
    auto column = [&](const YAML::Node& key) {
        const std::string name = key.Scalar();
        if (auto it = column_ok.find(name); it != column_ok.end()) return it->second;
        auto [l, c] = where(key);
        const bool ok = check_column_name(name, file, l, c, problems);
        column_ok[name] = ok;
        if (ok) m.columns.push_back({name, l, c});
        return ok;
    };
    // A plain scalar goes to the loader as written (1e9 stays 1e9); a quoted one (tag "!") and
    // lists or maps are re-emitted as flow YAML, so that a quoted string keeps its quotes.
    auto yaml_text = [](const YAML::Node& v) {
        if (v.IsScalar() && v.Tag() != "!") return v.Scalar();
        YAML::Emitter e;
        e << YAML::Flow << v;
        return std::string(e.c_str());
    };
    struct Value {
        std::string text;
        int line, column;
        bool null;
    };
    std::vector<std::pair<std::string, Value>> default_cells;
    if (has_defaults)
        for (auto it = defaults.begin(); it != defaults.end(); ++it) {
            if (!column(it->first)) continue;
            auto [l, c] = where(it->second.IsNull() ? it->first : it->second);
            if (it->first.Scalar() == "id") {
                problems.push_back({file, l, c, "", "id", "'defaults:' cannot give an id", "every row has its own id"});
                continue;
            }
            const bool plain = it->first.Scalar() == "pipeline" && it->second.IsScalar();
            default_cells.push_back({it->first.Scalar(), {plain ? it->second.Scalar() : yaml_text(it->second), l, c,
                                                           it->second.IsNull()}});
        }
    RowChecker checker(m, problems);
    for (std::size_t r = 0; r < rows.size(); ++r) {
        const YAML::Node n = rows[r];
        auto [line, col] = where(n);
        Row row;
        row.number = static_cast<int>(r + 1);
        row.line = line;
        if (!n.IsMap()) {
            problems.push_back({file, line, col, "", "", "row " + std::to_string(r + 1) + " is not a mapping",
                                "- {id: a, pipeline: p.yaml, node.param: value}"});
            continue;
        }
        std::vector<std::pair<std::string, Value>> cells = default_cells;
        bool has_id = false, bad = false;
        for (auto it = n.begin(); it != n.end(); ++it) {
            if (!column(it->first)) {
                bad = true;
                continue;
            }
            auto [l, c] = where(it->second.IsNull() ? it->first : it->second);
            const std::string key = it->first.Scalar();
            const bool plain = (key == "id" || key == "pipeline") && it->second.IsScalar();
            Value v{plain ? it->second.Scalar() : yaml_text(it->second), l, c, it->second.IsNull()};
            if (key == "id") {
                has_id = true;
                if (!it->second.IsScalar()) {
                    problems.push_back({file, l, c, "", "id", "row " + std::to_string(r + 1) + ": the id is not a text", kIdHint});
                    bad = true;
                }
                row.id = v.text, row.id_column = c, row.line = l;
                continue;
            }
            bool replaced = false;
            for (auto& [k, old] : cells)
                if (k == key) old = v, replaced = true;
            if (!replaced) cells.push_back({key, v});
        }
        if (bad && row.id.empty()) continue;
        bool has_pipeline = false;
        for (const auto& [k, v] : cells) {
            if (k == "pipeline") {
                has_pipeline = !v.null;
                row.pipeline_text = v.text, row.pipeline_line = v.line, row.pipeline_column = v.column;
            } else if (!v.null) {
                // Override values go to the loader as YAML text; a scalar is re-emitted so that a
                // quoted string keeps its quotes.
                row.overrides.push_back({k, v.text, v.line, v.column});
            }
        }
        checker.add(std::move(row), has_id, has_pipeline);
    }
    return m;
}

Manifest read_manifest(const std::string& path, std::vector<Problem>& problems) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        problems.push_back({path, 0, 0, "", "", "cannot open the manifest file", "check the path"});
        Manifest m;
        m.file = path;
        return m;
    }
    std::stringstream ss;
    ss << in.rdbuf();
    const std::string ext = fs::path(path).extension().string();
    if (ext == ".yaml" || ext == ".yml") return parse_manifest_yaml(ss.str(), path, problems);
    if (ext != ".csv") {
        problems.push_back({path, 0, 0, "", "", "unknown manifest format '" + ext + "'",
                            "name the manifest .csv (comma-separated, header line) or .yaml/.yml (rows: list)"});
        Manifest m;
        m.file = path;
        return m;
    }
    return parse_manifest_csv(ss.str(), path, problems);
}

std::vector<std::string> set_arguments(const Row& row) {
    std::vector<std::string> r;
    for (const auto& c : row.overrides) r.push_back(c.column + "=" + c.value);
    return r;
}

}  // namespace cf::runtime::batch
