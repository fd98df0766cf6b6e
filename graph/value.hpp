#pragma once
// Type-erased immutable values that flow between nodes, and the stable type names that
// pipelines and error messages use for them. graph/ knows nothing of fracture: every domain
// type is named by the module that defines its nodes, with CF_GRAPH_TYPE.
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <typeindex>
#include <vector>

namespace cf::graph {

// Specialise (through CF_GRAPH_TYPE) to give a C++ type a stable name for YAML and docs.
template <class T>
struct TypeName;

struct TypeId {
    std::type_index index{typeid(void)};
    std::string name = "none";
    bool operator==(const TypeId& o) const { return index == o.index; }
    bool operator!=(const TypeId& o) const { return !(*this == o); }
};

template <class T>
TypeId type_id() {
    return TypeId{std::type_index(typeid(T)), std::string(TypeName<T>::value)};
}

// An immutable, shared value. Copying a Value never copies the payload: heavy data (dense
// blocks, grids) is shared between a writer of step k and the solver of step k+1.
class Value {
public:
    Value() : type_{std::type_index(typeid(void)), "none"} {}

    template <class T>
    static Value of(T v) {
        return Value(std::make_shared<const T>(std::move(v)), type_id<T>());
    }
    template <class T>
    static Value shared(std::shared_ptr<const T> p) {
        return Value(std::move(p), type_id<T>());
    }

    bool empty() const { return !data_; }
    const TypeId& type() const { return type_; }

    template <class T>
    std::shared_ptr<const T> ptr() const {
        if (!data_) throw std::logic_error("value is empty, expected " + std::string(TypeName<T>::value));
        if (type_.index != std::type_index(typeid(T)))
            throw std::logic_error("value has type " + type_.name + ", expected " + std::string(TypeName<T>::value));
        return std::static_pointer_cast<const T>(data_);
    }
    template <class T>
    const T& get() const { return *ptr<T>(); }

private:
    Value(std::shared_ptr<const void> d, TypeId t) : data_(std::move(d)), type_(std::move(t)) {}
    std::shared_ptr<const void> data_;
    TypeId type_;
};

}  // namespace cf::graph

// Give a C++ type its stable pipeline name. Use at global namespace scope.
#define CF_GRAPH_TYPE(T, NAME)                                  \
    template <>                                                 \
    struct cf::graph::TypeName<T> {                             \
        static constexpr std::string_view value = NAME;         \
    }

// Built-in value types usable by any node.
CF_GRAPH_TYPE(bool, "Bool");
CF_GRAPH_TYPE(long long, "Int");
CF_GRAPH_TYPE(double, "Real");
CF_GRAPH_TYPE(std::string, "String");
CF_GRAPH_TYPE(std::vector<double>, "RealList");
