#pragma once
// A minimal streaming JSON writer (commas and escaping handled), for reports.
#include <sstream>
#include <string>
#include <vector>

namespace cf::graph {

class JsonWriter {
public:
    JsonWriter& begin_object();
    JsonWriter& end_object();
    JsonWriter& begin_array();
    JsonWriter& end_array();
    JsonWriter& key(const std::string& k);
    JsonWriter& value(const std::string& s);
    JsonWriter& value(const char* s) { return value(std::string(s)); }
    JsonWriter& value(double d);   // non-finite numbers become null
    JsonWriter& value(long long i);
    JsonWriter& value(int i) { return value(static_cast<long long>(i)); }
    JsonWriter& value(bool b);
    JsonWriter& null();
    std::string str() const { return out_.str(); }

    static std::string escape(const std::string& s);

private:
    void before_value();
    std::ostringstream out_;
    std::vector<bool> first_;  // per open container: no element written yet
    bool after_key_ = false;
};

}  // namespace cf::graph
