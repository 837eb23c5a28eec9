#include "ist_fixture.h"

#include <doctest/doctest.h>

namespace sepal_test {

sepal::GenerateOptions ist_case_options() {
    sepal::GenerateOptions g;
    g.width = g.height = 24;
    g.materials = 4;
    g.views = 8;
    g.lights = 32;
    g.lobe_lights = 12;
    return g;
}

sepal::DecomposeOptions ist_decompose_options(sepal::IstMethod m) {
    sepal::DecomposeOptions o;
    o.method = m;
    o.terms = 4;
    o.restarts = 2;
    o.iterations = 40;
    return o;
}

const IstCase& ist_case() {
    static const IstCase c = [] {
        IstCase x;
        std::string err;
        REQUIRE_MESSAGE(sepal::generate_svbrdf(ist_case_options(), &x.svbrdf, &x.truth, &err), err);
        REQUIRE_MESSAGE(sepal::decompose_svbrdf(x.svbrdf, ist_decompose_options(sepal::IstMethod::SACLS), &x.sacls, &err), err);
        return x;
    }();
    return c;
}

const sepal::ShadeTree& ist_case_tree() {
    static const sepal::ShadeTree t = [] {
        sepal::ShadeTree tree;
        sepal::TreeOptions o;
        o.res = 16;
        std::string err;
        REQUIRE_MESSAGE(sepal::build_tree(ist_case().sacls, o, &tree, &err), err);
        return tree;
    }();
    return t;
}

}  // namespace sepal_test
