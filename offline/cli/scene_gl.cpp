// Scene frames on GL ES through the headless port (offline/cli is the part of offline/ that
// may use a port).
#include <GLES2/gl2.h>

#include "cli/scene_file.h"
#include "common/render_gl.h"

namespace sepal {

bool render_scene_gl(const LoadedScene& s, const SceneFrame& fr, const SceneGlOptions& opt, std::vector<uint8_t>* rgba,
                     SceneGlInfo* info, std::string* err) {
    sepal_ports::SceneSetup setup;
    setup.width = fr.desc.viewport[2];
    setup.height = fr.desc.viewport[3];
    sepal_ports::GlRenderOptions go;
    go.gles_version = opt.gles_version;
    go.mask = opt.mask;
    go.mode = opt.mode;
    go.framebuffer = opt.framebuffer;
    go.frames = opt.frames;
    std::vector<std::unique_ptr<sepal_material>> materials;
    std::vector<float> scratch(sepal_draw_scratch_floats(int(s.max_vertices()), fr.light_count));
    sepal_caps caps{};
    sepal_ports::HeadlessJob job;
    job.create = [&](sepal_caps* c, sepal_error* e) {
        caps = *c;
        for (const auto& a : s.assets) {
            materials.push_back(std::make_unique<sepal_material>());
            if (sepal_material_create(&caps, a.get(), setup.width, setup.height, materials.back().get(), e) != SEPAL_OK) {
                materials.pop_back();
                return false;
            }
        }
        return true;
    };
    job.draw = [&](sepal_draw_stats* stats, sepal_error* e) {
        if (opt.before) {
            opt.before();
        } else {
            glClearColor(fr.desc.clear_color[0], fr.desc.clear_color[1], fr.desc.clear_color[2], 1.0f);
            glClearDepthf(1.0f);
            glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        }
        sepal_frame_desc d = fr.desc;
        d.caps = &caps;
        d.clear = 0;
        d.scratch = scratch.data();
        d.scratch_floats = scratch.size();
        sepal_frame frame;
        if (sepal_frame_begin(&frame, &d, e) != SEPAL_OK) return false;
        *stats = sepal_draw_stats{};
        bool ok = true;
        std::vector<int> order = opt.order;
        if (order.empty())
            for (size_t i = 0; i < fr.objects.size(); ++i) order.push_back(int(i));
        for (size_t k = 0; ok && k < order.size(); ++k) {
            const size_t i = size_t(order[k]);
            if (i >= fr.objects.size()) {
                std::snprintf(e->message, sizeof e->message, "draw order names object %zu of %zu", i, fr.objects.size());
                ok = false;
                break;
            }
            const sepal_mesh mesh = s.meshes[size_t(s.object_mesh[i])].mesh();
            sepal_object o = fr.objects[i];
            o.material = materials[size_t(s.file.objects[i].material)].get();
            o.mesh = &mesh;
            o.lights = fr.lights;
            o.mode = opt.mode;
            sepal_draw_stats st = {};
            ok = sepal_frame_draw(&frame, &o, &st, e) == SEPAL_OK;
            stats->draw_calls += st.draw_calls;
            stats->fullscreen_passes += st.fullscreen_passes;
            stats->copies += st.copies;
            stats->doublings += st.doublings;
            stats->dim_lights += st.dim_lights;
        }
        sepal_error end_err = {};
        const bool ended = sepal_frame_end(&frame, &end_err) == SEPAL_OK;
        if (ok && !ended) *e = end_err;
        return ok && ended;
    };
    job.destroy = [&] {
        info->accumulates = !materials.empty();
        for (auto& m : materials) {
            sepal_material_info mi;
            sepal_material_get_info(m.get(), &mi);
            info->accumulates = info->accumulates && mi.accumulates;
            sepal_material_destroy(m.get());
        }
    };
    sepal_ports::GlRenderInfo gi;
    if (!sepal_ports::run_headless(setup, go, job, rgba, &gi, err)) return false;
    info->stats = gi.stats;
    info->device = gi.device;
    info->ms = gi.ms;
    return true;
}

}  // namespace sepal
