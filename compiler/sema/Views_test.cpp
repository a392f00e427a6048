// The table of views: every name is found back, the list the messages give names each one,
// and a scene accepts exactly these names for `view` (any other is the UnknownView error).
#include "compiler/sema/Views.h"
#include "tests/support/Support.h"

#include <doctest/doctest.h>

using namespace moire;

TEST_CASE("views: every view's name is found back, and the list names each one") {
    REQUIRE(sema::viewNames().size() >= 3);
    for (const sema::ViewName& v : sema::viewNames()) {
        CAPTURE(v.name);
        REQUIRE(sema::viewNamed(v.name));
        CHECK(*sema::viewNamed(v.name) == v.mode);
        CHECK(std::string(sema::viewName(v.mode)) == v.name);
        CHECK(sema::viewList().find(v.name) != std::string::npos);
        auto program = test::compileOk(std::string("scene { view = ") + v.name +
                                       " }\nlayer { family = circles }\n");
        CHECK(program->view == v.mode);
    }
    CHECK(sema::viewList() == "pattern, envelope, split or ratio");
    CHECK(!sema::viewNamed("Envelope"));
    CHECK(!sema::viewNamed(""));
    CHECK(test::compileErrors("scene { view = 3 }\nlayer { family = circles }\n")
              .find("this is not a view") != std::string::npos);
}
