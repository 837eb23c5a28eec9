#include "bake/plan.h"

#include <algorithm>
#include <cmath>

#include "bake/quantize.h"

namespace sepal {
namespace {

struct Coef {
    sepal_pass_op op;
    uint16_t tex0, tex1;
    double value[3];
};

}  // namespace

double partial_sum_peak(const AssetData& a) {
    const size_t count = a.textures.size();
    if (count == 0 || a.passes.empty()) return 0.0;
    for (const AssetTexture& t : a.textures)
        if (t.data.empty() || t.desc.width != a.textures[0].desc.width) return 0.0;
    const int channels = int(a.material.channels);
    const size_t n = size_t(a.textures[0].desc.width) * a.textures[0].desc.height;
    size_t stride = 1;
    while ((n / stride) * (n / stride) > (size_t(1) << 22)) ++stride;
    const double margin = stride > 1 ? 1.25 : 1.0;
    auto q = [&](const AssetTexture& t, size_t i, int c) {
        return texel_q(t, i * t.desc.channels + size_t(c < int(t.desc.channels) ? c : 0));
    };
    double peak = 0;
    // Every added pass reads a G texture at texel i and an H texture at texel j (or one of
    // them, or none): the partial sum at (i, j) after all adds.
    for (int c = 0; c < 3; ++c)
        for (size_t i = 0; i < n; i += stride)
            for (size_t j = 0; j < n; j += stride) {
                double sum = 0;
                for (const sepal_fmt_pass& p : a.passes) {
                    if (p.blend != SEPAL_BLEND_ADD) break;
                    double v = p.color[c];
                    for (uint16_t tex : {p.tex0, p.tex1}) {
                        if (tex == SEPAL_FMT_NO_TEXTURE) continue;
                        const AssetTexture& t = a.textures[tex];
                        v *= q(t, t.desc.role == SEPAL_ROLE_G ? i : j, channels == 1 ? 0 : c);
                    }
                    sum += v;
                }
                peak = std::max(peak, sum);
            }
    return peak * margin;
}

bool plan_all_zero(const AssetData& a) {
    for (const sepal_fmt_pass& p : a.passes)
        for (float c : p.color)
            if (c != 0.0f) return false;
    return !a.passes.empty();
}

bool build_plan(AssetData* a, std::string* err, bool allow_all_zero) {
    const uint32_t terms = a->material.terms;
    const int channels = int(a->material.channels);
    for (int c = 0; c < 3; ++c)
        if (!(a->material.ratio[c] >= 0.0f) || !std::isfinite(a->material.ratio[c])) {
            if (err) *err = "plan: the material's colour ratio must be finite and >= 0";
            return false;
        }
    std::vector<int> g(terms, -1), h(terms, -1);
    for (size_t i = 0; i < a->textures.size(); ++i) {
        const sepal_fmt_texture& d = a->textures[i].desc;
        if (d.term >= terms || d.role >= SEPAL_ROLE_COUNT) {
            if (err) *err = "plan: texture " + std::to_string(i) + " has a bad term or role";
            return false;
        }
        (d.role == SEPAL_ROLE_G ? g : h)[d.term] = int(i);
    }
    std::vector<Coef> coefs;
    for (uint32_t k = 0; k < terms; ++k) {
        if (g[k] < 0 || h[k] < 0) {
            if (err) *err = "plan: term " + std::to_string(k) + " lacks its G or H texture";
            return false;
        }
        const sepal_fmt_texture& G = a->textures[size_t(g[k])].desc;
        const sepal_fmt_texture& H = a->textures[size_t(h[k])].desc;
        Coef prod{SEPAL_OP_PRODUCT, uint16_t(g[k]), uint16_t(h[k]), {0, 0, 0}};
        Coef tg{SEPAL_OP_TEXTURE, uint16_t(g[k]), SEPAL_FMT_NO_TEXTURE, {0, 0, 0}};
        Coef th{SEPAL_OP_TEXTURE, uint16_t(h[k]), SEPAL_FMT_NO_TEXTURE, {0, 0, 0}};
        Coef cst{SEPAL_OP_CONSTANT, SEPAL_FMT_NO_TEXTURE, SEPAL_FMT_NO_TEXTURE, {0, 0, 0}};
        for (int c = 0; c < 3; ++c) {
            // One channel (luminance): the texture's channel 0, times the material's ratio.
            const int t = channels == 1 ? 0 : c;
            const double ratio = a->material.ratio[c];
            if (!(G.scale[t] >= 0) || !(H.scale[t] >= 0)) {
                if (err) *err = "plan: texture scales must be >= 0 (term " + std::to_string(k) + ")";
                return false;
            }
            prod.value[c] = ratio * G.scale[t] * H.scale[t];
            tg.value[c] = ratio * G.scale[t] * H.bias[t];
            th.value[c] = ratio * G.bias[t] * H.scale[t];
            cst.value[c] = ratio * G.bias[t] * H.bias[t];
        }
        if (a->material.flags & SEPAL_MATERIAL_RECIPROCAL) {
            // G H G (homomorphic, format 2.1): one RECIPROCAL pass per term, G's scale twice.
            // The factors are positive (exp of a log fit): a bias would need the cross terms
            // of a triple product, which no pass draws.
            for (int c = 0; c < 3; ++c) {
                const int t = channels == 1 ? 0 : c;
                if (G.bias[t] != 0 || H.bias[t] != 0) {
                    if (err) *err = "plan: a reciprocal term's textures must have bias 0 (term " + std::to_string(k) + ")";
                    return false;
                }
                prod.value[c] *= G.scale[t];
            }
            prod.op = SEPAL_OP_RECIPROCAL;
            coefs.push_back(prod);
            continue;
        }
        for (const Coef& c : {prod, tg, th, cst}) coefs.push_back(c);
    }
    // A radiance material's diffuse part: one untextured pass whose colour the runtime
    // multiplies by E cos(theta_i) (format 2).
    const float* d = a->material.diffuse;
    if (d[0] > 0 || d[1] > 0 || d[2] > 0) {
        for (int c = 0; c < 3; ++c)
            if (!(d[c] >= 0) || !std::isfinite(d[c])) {
                if (err) *err = "plan: the diffuse part must be finite and >= 0";
                return false;
            }
        coefs.push_back(Coef{SEPAL_OP_DIFFUSE, SEPAL_FMT_NO_TEXTURE, SEPAL_FMT_NO_TEXTURE, {d[0], d[1], d[2]}});
    }
    // Split by sign per channel into added and subtracted passes.
    std::vector<std::pair<sepal_blend, Coef>> passes;
    for (sepal_blend blend : {SEPAL_BLEND_ADD, SEPAL_BLEND_SUBTRACT})
        for (const Coef& c : coefs) {
            Coef part = c;
            bool any = false;
            for (int ch = 0; ch < 3; ++ch) {
                const double v = c.value[ch];
                const bool mine = blend == SEPAL_BLEND_ADD ? v > 0 : v < 0;
                part.value[ch] = mine ? std::fabs(v) : 0.0;
                any = any || mine;
            }
            if (any) passes.push_back({blend, part});
        }
    if (passes.empty()) {
        if (!allow_all_zero) {
            if (err) *err = "plan: every coefficient is zero (an all-zero BRDF?)";
            return false;
        }
        // The reader needs a pass; a constant one reads no texture and adds 0.
        a->passes.clear();
        sepal_fmt_pass zero{};
        zero.op = uint16_t(SEPAL_OP_CONSTANT);
        zero.blend = uint16_t(SEPAL_BLEND_ADD);
        zero.tex0 = zero.tex1 = SEPAL_FMT_NO_TEXTURE;
        zero.rgb_scale = 1;
        a->passes.push_back(zero);
        a->plan = sepal_fmt_plan{};
        a->plan.pass_count = 1;
        a->plan.doublings = 0;
        a->plan.peak_partial_sum = 1e-30f;  // the same floor as below: (0, 1] is required
        return true;
    }
    double added[3] = {0, 0, 0}, biggest = 0;
    for (const auto& p : passes)
        for (int ch = 0; ch < 3; ++ch) {
            if (p.first == SEPAL_BLEND_ADD) added[ch] += p.second.value[ch];
            biggest = std::max(biggest, p.second.value[ch]);
        }
    const double peak = std::max({added[0], added[1], added[2], biggest});
    // Smallest D with peak * 2^-D <= 1; negative D would scale up at no cost, but the
    // runtime's exposure already uses the headroom per frame.
    int doublings = 0;
    while (std::ldexp(peak, -doublings) > 1.0) ++doublings;
    if (doublings > SEPAL_FMT_MAX_DOUBLINGS) {
        if (err) *err = "plan: coefficients up to " + std::to_string(peak) + " need more than " +
                        std::to_string(SEPAL_FMT_MAX_DOUBLINGS) + " doublings (f beyond about " +
                        std::to_string(1 << SEPAL_FMT_MAX_DOUBLINGS) + "/sr): clamp the peaks (sepal bake --cap)";
        return false;
    }
    a->passes.clear();
    for (const auto& p : passes) {
        sepal_fmt_pass out{};
        out.op = uint16_t(p.second.op);
        out.blend = uint16_t(p.first);
        out.tex0 = p.second.tex0;
        out.tex1 = p.second.tex1;
        for (int ch = 0; ch < 3; ++ch)
            out.color[ch] = float(std::min(1.0, std::ldexp(p.second.value[ch], -doublings)));
        out.rgb_scale = 1;
        a->passes.push_back(out);
    }
    a->plan = sepal_fmt_plan{};
    a->plan.pass_count = uint32_t(a->passes.size());
    a->plan.doublings = uint32_t(doublings);
    // The bound sum-of-added-colours assumes every texture at 1 at once; the real peak
    // over texel pairs is usually far lower, and the runtime's exposure uses it.
    const double bound = std::ldexp(std::max({added[0], added[1], added[2]}), -doublings);
    const double real = partial_sum_peak(*a);
    a->plan.peak_partial_sum = float(std::min(1.0, std::max(1e-30, real > 0 ? std::min(real, bound) : bound)));
    return true;
}

double plan_value(const AssetData& a, const double* q, int channel, const double* q_swapped) {
    double sum = 0;
    for (const sepal_fmt_pass& p : a.passes) {
        double v = p.color[channel];
        if (p.op == SEPAL_OP_PRODUCT || p.op == SEPAL_OP_TEXTURE || p.op == SEPAL_OP_RECIPROCAL) v *= q[p.tex0];
        if (p.op == SEPAL_OP_PRODUCT || p.op == SEPAL_OP_RECIPROCAL) v *= q[p.tex1];
        if (p.op == SEPAL_OP_RECIPROCAL) v *= (q_swapped ? q_swapped : q)[p.tex0];
        sum += p.blend == SEPAL_BLEND_ADD ? v : -v;
    }
    return std::ldexp(sum, int(a.plan.doublings));
}

}  // namespace sepal
