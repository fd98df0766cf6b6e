#include "nodes/rigid/scene_report.hpp"

#include "graph/atomic_write.hpp"
#include "graph/json_writer.hpp"

#include <iomanip>
#include <ostream>

namespace cf::rigid {

namespace {
std::string csv_text(std::string s) {  // inside double quotes: quotes doubled, line breaks as spaces
    std::string out;
    for (char ch : s) {
        if (ch == '"') out += "\"\"";
        else if (ch == '\n' || ch == '\r') out += ' ';
        else out += ch;
    }
    return out;
}
}  // namespace

void write_fracture_runs(const std::filesystem::path& stem, const std::vector<FractureRunRecord>& runs) {
    std::filesystem::path csv = stem, json = stem;
    csv += ".csv";
    json += ".json";
    graph::write_atomically(csv, [&](std::ostream& os) {
        os << std::setprecision(9);
        os << "frame,body,impulse_Ns,force_N,contact_duration_s,max_steps,bem_triangles,fragments,dropped,crack_triangles,carried_triangles,old_crack_triangles_start,old_crack_triangles_end,seconds,broke,error\n";
        for (const FractureRunRecord& r : runs)
            os << r.frame << ',' << r.body << ',' << r.impulse << ',' << r.force << ',' << r.contact_duration << ','
               << r.max_steps << ',' << r.bem_triangles << ',' << r.fragments << ',' << r.dropped << ',' << r.crack_triangles << ','
               << r.carried_triangles << ',' << r.old_crack_triangles_start << ',' << r.old_crack_triangles_end << ','
               << r.seconds
               << ',' << (r.broke ? 1 : 0) << ",\"" << csv_text(r.error) << "\"\n";
    });
    graph::JsonWriter w;
    w.begin_object().key("fracture_runs").begin_array();
    for (const FractureRunRecord& r : runs) {
        w.begin_object();
        w.key("frame").value(r.frame).key("body").value(r.body).key("impulse_Ns").value(r.impulse);
        w.key("force_N").value(r.force).key("contact_duration_s").value(r.contact_duration);
        w.key("max_steps").value(r.max_steps).key("bem_triangles").value(static_cast<long long>(r.bem_triangles));
        w.key("fragments").value(r.fragments).key("dropped").value(r.dropped).key("seconds").value(r.seconds);
        w.key("broke").value(r.broke);
        if (!r.error.empty()) w.key("error").value(r.error);
        w.end_object();
    }
    w.end_array().end_object();
    const std::string text = w.str() + "\n";
    graph::write_atomically(json, [&](std::ostream& os) { os << text; });
}

}  // namespace cf::rigid
