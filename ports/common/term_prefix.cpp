#include "common/term_prefix.h"

#include <math.h>
#include <string.h>

namespace sepal_ports {
namespace {

// The term of a CONSTANT pass: the one whose bias product, scaled like the plan, equals
// its colour in every nonzero channel. -1 when none or several do.
int constant_pass_term(const sepal_asset& a, const sepal_fmt_pass& pass) {
    int g[SEPAL_FMT_MAX_TERMS], h[SEPAL_FMT_MAX_TERMS];
    for (uint32_t i = 0; i < a.texture_count; ++i)
        (a.textures[i].desc.role == SEPAL_ROLE_G ? g : h)[a.textures[i].desc.term] = (int)i;
    const float scale = ldexpf(1.0f, -(int)a.plan.doublings);
    int found = -1;
    for (uint32_t k = 0; k < a.material.terms; ++k) {
        bool match = true, any = false;
        for (int c = 0; c < 3 && match; ++c) {
            if (pass.color[c] == 0.0f) continue;
            const int t = a.material.channels == 1 ? 0 : c;
            const float want = fabsf(a.material.ratio[c] * a.textures[g[k]].desc.bias[t] *
                                     a.textures[h[k]].desc.bias[t]) * scale;
            match = fabsf(want - pass.color[c]) <= 1e-3f * pass.color[c];
            any = true;
        }
        if (match && any) {
            if (found >= 0) return -1;
            found = (int)k;
        }
    }
    return found;
}

}  // namespace

TermPrefix term_prefix(const sepal_asset& in, int terms, sepal_asset* out) {
    memcpy(out, &in, sizeof in);
    TermPrefix r;
    const int all = (int)in.material.terms;
    r.terms = terms < 1 || terms > all ? all : terms;
    out->material.terms = (uint32_t)r.terms;
    uint32_t kept = 0;
    for (uint32_t p = 0; p < in.plan.pass_count; ++p) {
        const sepal_fmt_pass& pass = in.passes[p];
        int term = -1;
        if (pass.op == SEPAL_OP_PRODUCT || pass.op == SEPAL_OP_TEXTURE || pass.op == SEPAL_OP_RECIPROCAL) {
            term = (int)in.textures[pass.tex0].desc.term;
            if (pass.op != SEPAL_OP_TEXTURE && (int)in.textures[pass.tex1].desc.term > term)
                term = (int)in.textures[pass.tex1].desc.term;
        } else if (pass.op == SEPAL_OP_CONSTANT) {
            term = constant_pass_term(in, pass);
        } else if (pass.op == SEPAL_OP_DIFFUSE) {
            term = 0;  // the separated diffuse part belongs to every prefix, like the CPU's sum
        }
        if (term < 0) ++r.unattributed;
        if (term < r.terms) out->passes[kept++] = pass;
    }
    // Keep at least one pass (the reader's rule); an all-dropped plan cannot happen for
    // k >= 1, since term 0's product pass is always kept.
    out->plan.pass_count = kept > 0 ? kept : 1;
    r.passes = (int)out->plan.pass_count;
    for (uint32_t i = 0; i < in.texture_count; ++i) {
        const sepal_fmt_texture& d = in.textures[i].desc;
        if ((int)d.term >= r.terms) continue;
        uint32_t w = d.width, h = d.height;
        for (uint32_t level = 0; level < d.levels; ++level, w = w > 1 ? w / 2 : 1, h = h > 1 ? h / 2 : 1)
            r.texture_bytes += (size_t)w * h * d.channels;
    }
    return r;
}

}  // namespace sepal_ports
