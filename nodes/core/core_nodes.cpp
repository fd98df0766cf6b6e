// Generic nodes: constants, arithmetic and comparisons on reals, and writing a value to a
// text file. They carry no physics; pipelines use them for loop control (e.g. stop after a
// condition) and the graph tests use them to exercise loops and streaming.
#include "graph/atomic_write.hpp"
#include "graph/node_context.hpp"
#include "nodes/registration.hpp"

#include <cmath>
#include <cstdio>
#include <thread>

namespace cf {

void register_core_nodes(graph::NodeRegistry& r) {
    {
        graph::NodeType t("core.real", "A constant real number.");
        t.output<double>("value", "the constant");
        t.param_real("value", 0.0, "", "the number (any unit; document it where it is used)");
        t.run([](graph::NodeContext& c) { c.out("value", c.real("value")); });
        r.add(std::move(t));
    }
    {
        graph::NodeType t("core.add", "Sum of two reals: sum = a + b.");
        t.input<double>("a", "first term").input<double>("b", "second term");
        t.output<double>("sum", "a + b");
        t.run([](graph::NodeContext& c) { c.out("sum", c.in<double>("a") + c.in<double>("b")); });
        r.add(std::move(t));
    }
    {
        graph::NodeType t("core.less", "Comparison of two reals: result = a < b (for loop 'while' conditions).");
        t.input<double>("a", "left side").input<double>("b", "right side");
        t.output<bool>("result", "a < b");
        t.run([](graph::NodeContext& c) { c.out("result", c.in<double>("a") < c.in<double>("b")); });
        r.add(std::move(t));
    }
    {
        graph::NodeType t("core.wait",
                          "Passes a real through after holding it for a given time; used to demonstrate and test "
                          "concurrency of independent branches.");
        t.input<double>("value", "the value to pass on");
        t.output<double>("value", "the same value");
        t.param_real("seconds", 0.1, "s", "how long to hold the value").range(0, 60);
        t.run([](graph::NodeContext& c) {
            const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(c.real("seconds"));
            while (std::chrono::steady_clock::now() < until) {
                c.check_cancelled();
                std::this_thread::sleep_for(std::chrono::milliseconds(5));
            }
            c.out("value", c.in<double>("value"));
        });
        r.add(std::move(t));
    }
    {
        graph::NodeType t("core.write_real",
                          "Writes a real number as text to a file (atomically); '{iteration}' in the path becomes the "
                          "loop iteration (4 digits), so per-iteration values land in separate files.");
        t.input<double>("value", "the number to write");
        t.param_string("path", "value.txt", "output file, relative to the run's output directory").required().writes_file();
        t.run([](graph::NodeContext& c) {
            const std::filesystem::path p = c.output_path(c.string("path"));
            const double v = c.in<double>("value");
            graph::write_atomically(p, [&](std::ostream& o) {
                char buf[40];
                std::snprintf(buf, sizeof buf, "%.17g\n", v);
                o << buf;
            });
            c.count("bytes", static_cast<double>(std::filesystem::file_size(p)));
        });
        r.add(std::move(t));
    }
}

}  // namespace cf
