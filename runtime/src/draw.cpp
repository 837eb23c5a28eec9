// sepal_draw: validation, per-vertex set-up and exposure shared by the GL backends (and the
// GL ES 1.1 emulator), then dispatch to the GL ES 1.1 or GL ES 2 executor.
#include <math.h>
#include <string.h>

#include "draw_internal.h"

namespace srt {

sepal_result prepare_frame(const sepal_draw_desc* d, const MeshView& mesh, const float modelview[16],
                           const float proj[16], bool float_target, FramePrep* out, sepal_draw_stats* stats,
                           sepal_error* err) {
    if (!d || !d->material || !d->scene || !d->scratch)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "draw: NULL material, mesh, scene or scratch");
    const srt::Material* m = srt::material(d->material);
    if (m->plan.pass_count == 0)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "draw: material not created (or destroyed)");
    if (d->width < 1 || d->height < 1 || d->width > m->max_width || d->height > m->max_height)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                         "draw: viewport %dx%d outside 1x1..%dx%d (the size given at creation)",
                         d->width, d->height, m->max_width, m->max_height);
    if (!mesh.attr[MeshView::kPosition] || !mesh.indices || mesh.vertex_count < 1 || mesh.index_count % 3)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "draw: empty or malformed mesh");
    const size_t need = sepal_draw_scratch_floats(mesh.vertex_count, d->scene->light_count);
    if (d->scratch_floats < need)
        return srt::fail(err, SEPAL_ERR_CAPACITY, "draw: scratch holds %zu floats, needs %zu",
                         d->scratch_floats, need);
    FramePrep& prep = *out;
    prep.mesh = mesh;
    memcpy(prep.view, modelview, sizeof prep.view);
    memcpy(prep.proj, proj, sizeof prep.proj);
    memset(stats, 0, sizeof *stats);
    prep.vertices = srt::setup_vertices((sepal_param)m->info.param, (sepal_hemi_map)m->info.map, mesh,
                                        *d->scene, d->scratch, (m->info.flags & SEPAL_MATERIAL_RECIPROCAL) != 0);
    const srt::TriangleCheck tri = srt::check_triangles(mesh, prep.vertices.bad_vertices);
    if (tri.bad_index >= 0)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "draw: index %d is %u; the mesh has %d vertices",
                         tri.bad_index, mesh.indices[tri.bad_index], mesh.vertex_count);
    stats->below_horizon = prep.vertices.below_horizon;
    stats->dim_lights = dim_lights(m->info, mesh, *d->scene);
    stats->weaker_context = m->weaker != 0;
    stats->fallback_tangents = prep.vertices.fallback_tangents;
    stats->bad_vertices = prep.vertices.bad_vertices;
    stats->skipped_triangles = tri.skipped;
    stats->zero_area_triangles = tri.zero_area;
    stats->param_fallbacks = prep.vertices.param_fallbacks;
    stats->nonfinite_clamped = prep.vertices.nonfinite_clamped;
    // Exposure 2^-e: no partial sum over the lights above 1, no vertex colour above 1.
    const int plan_doublings = (int)m->plan.doublings;
    int e = -plan_doublings;
    // A float target holds any value: no headroom, no exposure, no doublings.
    const bool radiance = (m->info.flags & SEPAL_MATERIAL_RADIANCE) != 0;
    // Only a plan that subtracts needs headroom: without subtractions a partial sum never
    // exceeds the final value, and a final value above 1 is white on screen either way.
    // (A radiance material's sum is bounded with E alone: cos(theta_i) <= 1.)
    const float irradiance_sum = radiance ? prep.vertices.max_lit_sum : prep.vertices.max_irradiance_sum;
    // Nor does a diffuse map (a tree's blend map) hold: the framebuffer is multiplied by it
    // before the final doublings, so the sum itself must fit: a highlight of 3 under a
    // weight of 0.2 shows 0.6, not 0.2 (docs/ist.md).
    // Applied per pass (multipass with a third texture unit: GL ES 1.1's combiner, GL ES 2's
    // pass shader) it is a factor of each pass like its textures: no headroom for it.
    // Not for signed plans: their partial sums need headroom anyway, and each pass's own
    // 8-bit rounding under the map would move their cancellations.
    prep.diffuse_per_pass = d->diffuse_texture != 0 && !m->single_unit && m->caps.texture_units >= 3 &&
                            d->mode == SEPAL_MODE_MULTIPASS && !m->has_negative_passes;
    const bool headroom = m->has_negative_passes || (d->diffuse_texture != 0 && !prep.diffuse_per_pass);
    const float need_sum = headroom ? irradiance_sum * m->plan.peak_partial_sum : 0.0f;
    // Per pass, the largest value GL clamps at 1 (the vertex colour; on one texture unit also
    // colour x tex0, formed and clamped before the blend multiplies it by tex1, else a
    // product whose final value is below 1 comes out short: measured 13.5 levels on a
    // mirror scene), times the largest irradiance it is multiplied by this frame.
    float pass_peak[SEPAL_FMT_MAX_PASSES];
    float need_color = 0.0f;
    for (uint32_t p = 0; p < m->plan.pass_count; ++p) {
        pass_peak[p] = m->pass_need[p] * pass_irradiance_peak(prep.vertices, pass_uses_cosine(m->info, m->passes[p]));
        if (pass_peak[p] > need_color) need_color = pass_peak[p];
    }
    // The fused shaders compute f E directly: no exposure, no doublings.
    const bool fused = d->mode != SEPAL_MODE_MULTIPASS;
    // Past 2^-30 (irradiance times pass colour over 2^30, infinity included) the exposure
    // stops: vertex colours clamp at 1, the lit surface shows white, and it is counted.
    const int kMaxShift = 30;
    const float needs[2] = {need_sum, need_color};
    for (float n : needs) {
        if (float_target || !(n > 0.0f)) continue;
        const float shift = ceilf(log2f(n));
        const int want = shift < (float)kMaxShift ? (int)shift : kMaxShift + 1;
        if (want > e) e = want;
    }
    if (e > kMaxShift) {
        e = kMaxShift;
        if (!fused) stats->exposure_clamped = 1;
    }
    // Staged exposure (GL ES 1.1, add-only plans): each pass gets the largest exposure its
    // own colours allow; the frame's doublings are spread between the stages. Partial sums
    // only grow, so a stage that doubles past 1 was white on screen anyway.
    // Not with a diffuse map multiplying the framebuffer: a stage doubled past 1 clips before
    // the map multiplies it (measured on a tree: 26.3 dB staged, 31.3 not); a per-pass map is
    // in every pass already.
    prep.staged = m->caps.gles_version == 1 && !m->has_negative_passes && !fused && !float_target &&
                  (!d->diffuse_texture || prep.diffuse_per_pass);
    stats->exposure_stages = 1;
    if (prep.staged) {
        int previous = e + 1;
        stats->exposure_stages = 0;
        for (uint32_t p = 0; p < m->plan.pass_count; ++p) {
            int shift = -plan_doublings;
            if (pass_peak[p] > 0.0f) {
                const float want = ceilf(log2f(pass_peak[p]));
                if (want > (float)shift) shift = want < (float)e ? (int)want : e;
            }
            prep.pass_shift[p] = shift;
        }
        // Stages are the distinct shifts (the executor draws them in falling order).
        for (;;) {
            int next = -plan_doublings - 1;
            for (uint32_t p = 0; p < m->plan.pass_count; ++p)
                if (prep.pass_shift[p] < previous && prep.pass_shift[p] > next) next = prep.pass_shift[p];
            if (next < -plan_doublings) break;
            ++stats->exposure_stages;
            previous = next;
        }
    }
    prep.exposure = fused ? 1.0f : ldexpf(1.0f, -e);
    stats->exposure = prep.exposure;
    stats->doublings = fused ? 0 : plan_doublings + e;
    return SEPAL_OK;
}

void pass_order(const srt::Material* m, const FramePrep& prep, uint16_t* order) {
    // The plan's order; staged (add-only plans): by falling exposure shift, stable.
    const uint32_t count = m->plan.pass_count;
    for (uint32_t p = 0; p < count; ++p) {
        uint32_t k = p;
        for (; prep.staged && k > 0 && prep.pass_shift[order[k - 1]] < prep.pass_shift[p]; --k) order[k] = order[k - 1];
        order[k] = (uint16_t)p;
    }
}

int gles1_schedule(const srt::Material* m, const FramePrep& prep, int total_doublings, Gles1Step* steps) {
    uint16_t order[SEPAL_FMT_MAX_PASSES];
    const uint32_t count = m->plan.pass_count;
    pass_order(m, prep, order);
    int n = 0;
    int shift = count > 0 && prep.staged ? prep.pass_shift[order[0]] : 0;
    int remaining = total_doublings;  // doublings still to draw
    float exposure = prep.exposure;
    bool inverted = false;
    for (uint32_t i = 0; i < count; ++i) {
        const sepal_fmt_pass& pass = m->passes[order[i]];
        if (prep.staged && prep.pass_shift[order[i]] < shift) {
            // Next stage: double what is drawn so far up to this stage's exposure.
            steps[n++] = {Gles1Step::kDouble, shift - prep.pass_shift[order[i]], 0, 0.0f, inverted};
            remaining -= shift - prep.pass_shift[order[i]];
            shift = prep.pass_shift[order[i]];
            exposure = ldexpf(1.0f, -shift);
        }
        if (pass.blend == SEPAL_BLEND_SUBTRACT && m->subtract_by_inversion && !inverted) {
            steps[n++] = {Gles1Step::kInvert, 0, 0, 0.0f, false};
            inverted = true;
        }
        steps[n++] = {Gles1Step::kPass, 0, order[i], exposure, inverted};
    }
    if (inverted) steps[n++] = {Gles1Step::kInvert, 0, 0, 0.0f, true};
    steps[n++] = {Gles1Step::kDouble, remaining, 0, 0.0f, false};
    return n;
}

}  // namespace srt

extern "C" sepal_result sepal_draw(const sepal_draw_desc* d, sepal_draw_stats* stats_out, sepal_error* err) {
    if (d && d->material && srt::material(d->material)->texture_count == 0)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "draw: material not created (or destroyed)");
    if (d && d->material && srt::material(d->material)->context_lost)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                         "draw: the material's GL context was lost; sepal_material_restore it on the new context");
    if (!d || !d->scene)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "draw: NULL material, mesh, scene or scratch");
    // One object in a frame of its own: cleared, the scene's camera, the mesh as it is
    // (the world is its object space), the background where it does not cover.
    sepal_frame_desc fd = {};
    sepal_result r = sepal_scene_matrices(d->scene, d->width, d->height, fd.view, fd.projection, err);
    if (r != SEPAL_OK) return r;
    srt::FramePrep prep;
    sepal_draw_stats local_stats;
    sepal_draw_stats* stats = stats_out ? stats_out : &local_stats;
    const srt::Material* m = srt::material(d->material);
    if (!d->mesh) return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "draw: NULL material, mesh, scene or scratch");
    r = srt::prepare_frame(d, srt::MeshView(*d->mesh), fd.view, fd.projection, m && m->float_fbo != 0, &prep, stats,
                           err);
    if (r != SEPAL_OK) return r;
    fd.caps = &m->caps;
    fd.viewport[2] = d->width;
    fd.viewport[3] = d->height;
    fd.clear = 1;
    alignas(8) unsigned char saved[srt::kSavedStateBytes];
    if (m->caps.gles_version == 1) {
        srt::gles1_frame_begin(fd, saved);
        r = srt::draw_gles1(d, prep, stats, err);
        if (r == SEPAL_OK) srt::gles1_background(d->scene->background, stats);
        srt::gles1_frame_end(m->caps, saved);
    } else {
        srt::gles2_frame_begin(fd, saved, m->float_fbo);
        r = srt::draw_gles2(d, prep, stats, err);
        if (r == SEPAL_OK) {
            srt::gles2_background(m, d->scene->background, stats);
            if (m->float_fbo) srt::gles2_show_float(m, saved, d->width, d->height, stats);
        }
        srt::gles2_frame_end(m->caps, saved);
    }
    if (r != SEPAL_OK) return r;
    return srt::gl_check("the frame's end", err);
}
