// docs/nodes.md is generated from the registry; this fails when someone forgets to regenerate it.
#include "nodes/register_all.hpp"
#include "runtime/node_docs.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

TEST(NodeDocs, DocsNodesMdIsCurrent) {
    std::ifstream f(std::string(CRACKFLOW_SOURCE_DIR) + "/docs/nodes.md");
    ASSERT_TRUE(f) << "docs/nodes.md is missing; run: crackflow nodes --markdown > docs/nodes.md";
    std::stringstream ss;
    ss << f.rdbuf();
    EXPECT_TRUE(ss.str() == cf::runtime::nodes_markdown(cf::node_registry()))
        << "docs/nodes.md is out of date; regenerate it with: ./build/runtime/crackflow nodes --markdown > docs/nodes.md";
}

TEST(NodeDocs, EveryParameterAndPortIsDocumented) {
    for (const auto* t : cf::node_registry().all()) {
        EXPECT_FALSE(t->doc().empty()) << t->name();
        for (const auto& p : t->params()) EXPECT_FALSE(p.doc.empty()) << t->name() << "." << p.name;
        for (const auto& p : t->inputs()) EXPECT_FALSE(p.doc.empty()) << t->name() << " input " << p.name;
        for (const auto& p : t->outputs()) EXPECT_FALSE(p.doc.empty()) << t->name() << " output " << p.name;
    }
}
