// sepal-bench-fidelity: what a new user's default bake gives, measured (make bench).
//
//   build/bin/sepal-bench-fidelity [--out DIR] [--only NAME] [--threads N]
//
// For every material of the README's table and a few more chosen to be hard (sharp Phong and
// Blinn lobes, a two-lobe Lafortune, Cook-Torrance at roughness 0.05, the bounded-albedo Ward,
// Hapke-Lommel, Lambert): the default bake (sepal::bake with default options, exactly what
// `sepal bake SPEC` does), its wall time, then the asset drawn by llvmpipe on GL ES 1.1 and
// GL ES 2 (multipass) and by the CPU backend in the default scene (512x512, `sepal render`'s)
// and on GL ES 1.1 in the grazing view the bake also judges by: PSNR against the exact
// render (8-bit, as displayed), plan passes, the frame's doublings, asset bytes, the colour
// mode --colour auto chose, the winner; and the same bake within 8 KB (--max-bytes 8192,
// the size goal): its GL ES 1.1 PSNR and winner, or "none fits".
// Writes DIR/fidelity.json and DIR/fidelity.md (the README's table, generated). The machine's
// load average is recorded next to the times: they are wall-clock seconds of one bake with
// all cores, comparable only on a quiet machine.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "bench/bench_cli.h"
#include "bench/quiet.h"
#include "bench/json_builder.h"
#include "bake/asset_file.h"
#include "bake/bake.h"
#include "common/render_gl.h"
#include "common/scene_flags.h"
#include "reference/render_exact.h"
#include "spec/spec.h"
#include "util/image.h"
#include "util/io.h"

namespace {

struct Material {
    const char* name;
    std::string spec;
    bool issue_table;  // one of the twelve of the README's table
};

std::vector<Material> materials() {
    const std::string c = std::string(SEPAL_SOURCE_DIR) + "/fixtures/cornell/";
    return {
        {"ward", "ward", true},
        {"ward aniso", "ward:rho_d=0.4,rho_s=0.5,ax=0.4,ay=0.15", true},
        {"cook-torrance", "cook-torrance", true},
        {"velvet", "velvet", true},
        {"blinn", "blinn", true},
        {"oren-nayar", "oren-nayar", true},
        {"lafortune", "lafortune", true},
        {"ashikhmin-shirley", "ashikhmin-shirley", true},
        {"poulin-fournier", "poulin-fournier", true},
        {"cayman", c + "cayman.brdf", true},
        {"krylon_blue", c + "krylon_blue.brdf", true},
        {"garnet_red", c + "garnet_red.brdf", true},
        {"phong n=1000", "phong:n=1000", false},
        {"blinn n=2000", "blinn:n=2000", false},
        {"lafortune 2 lobes", "lafortune:rho_d=0.1,lobe=-1/-1/1/60/0.8,lobe=-0.5/-0.5/0.9/8/0.2", false},
        {"cook-torrance m=0.05", "cook-torrance:m=0.05", false},
        {"ward-duer aniso", "ward-duer:rho_d=0.4,rho_s=0.5,ax=0.4,ay=0.15", false},
        {"hapke-lommel", "hapke-lommel", false},
        {"lambert", "lambert", false},
    };
}

// The size goal (a material in 8 KB): each default material baked again with --max-bytes this.
constexpr int64_t kSmallBytes = 8192;

sepal::Image clamp8(sepal::Image img) {
    for (float& v : img.data) v = std::round(std::min(1.0f, std::max(0.0f, v)) * 255.0f) / 255.0f;
    return img;
}

double load_average() {
    double l = -1;
    if (std::FILE* f = std::fopen("/proc/loadavg", "r")) {
        if (std::fscanf(f, "%lf", &l) != 1) l = -1;
        std::fclose(f);
    }
    return l;
}

bool scene_of(const std::vector<std::string>& flags, sepal_ports::SceneSetup* s, std::string* err) {
    std::vector<std::string> words = flags;
    std::vector<char*> argv;
    for (std::string& w : words) argv.push_back(&w[0]);
    for (int i = 0; i < int(argv.size());) {
        const int used = sepal_ports::parse_scene_flag(int(argv.size()), argv.data(), i, s, err);
        if (used <= 0) return false;
        i += used;
    }
    return sepal_ports::load_scene_mesh(s, err);
}

}  // namespace

int main(int argc, char** argv) {
    BenchCli cli("sepal-bench-fidelity",
                 "The default bake of the README's materials and more: PSNR on gles1/gles2/cpu, passes, doublings, "
                 "bytes, bake seconds; writes OUT/fidelity.json and OUT/fidelity.md");
    cli.add_only_and_threads("one material label");
    if (const int code = cli.parse(argc, argv); code >= 0) return code;
    const std::string& only = cli.only;
    const int threads = cli.threads;
    const std::string& out = cli.out;
    std::string err;
    sepal_ports::SceneSetup def, grazing;
    if (!scene_of({}, &def, &err) || !scene_of({"--light", "point:3.83,1.91,0.96:60"}, &grazing, &err)) {
        std::fprintf(stderr, "bench: %s\n", err.c_str());
        return 1;
    }
    JsonBuilder j;
    j.begin_object().key("scene").value("default: 512x512 sphere, sepal render's camera and light");
    j.key("grazing").value("the same sphere and camera, --light point:3.83,1.91,0.96:60");
    j.key("reference").value("exact render, 4x4 samples per pixel (coverage at the pixel centre)");
    j.key("load_average_start").value(load_average());
    j.key("rows").begin_array();
    std::string md =
        "| material | gles1 dB | gles2 dB | cpu dB | gles1 grazing dB | exact 1x1 dB | passes | doublings | bytes | colour | bake s "
        "| winner | 8 KB gles1 dB | 8 KB winner |\n"
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|---|---:|---|\n";
    std::printf("%-22s %8s %8s %8s %8s %8s %6s %4s %8s %7s %8s %9s  %s\n", "material", "gles1", "gles2", "cpu", "grazing",
                "exact1", "passes", "dbl", "bytes", "bake s", "8KB", "colour", "winner | 8 KB winner");
    int failures = 0;
    for (const Material& m : materials()) {
        if (!only.empty() && only != m.name) continue;
        std::unique_ptr<sepal::Brdf> f = sepal::make_brdf(m.spec, &err);
        if (!f) {
            std::fprintf(stderr, "bench: %s: %s\n", m.name, err.c_str());
            ++failures;
            continue;
        }
        sepal::BakeOptions o;  // the defaults: what `sepal bake SPEC` does
        o.threads = threads;
        sepal::BakeResult r;
        double load = 0, seconds = 0;
        bool baked = false;
        {
            BenchQuiet quiet;  // the bake seconds are a README figure: the other lane waits
            load = load_average();
            const auto t0 = std::chrono::steady_clock::now();
            baked = sepal::bake(*f, o, &r, &err);
            seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        }
        std::vector<uint8_t> bytes;
        if (!baked || !sepal::encode_asset(r.asset, &bytes, &err)) {
            std::fprintf(stderr, "bench: %s: %s\n", m.name, err.c_str());
            ++failures;
            continue;
        }
        auto psnr_asset = [&](const std::vector<uint8_t>& bytes, const sepal_ports::SceneSetup& s,
                              const sepal::Image& exact, const char* backend, int* dbl) {
            sepal_ports::GlRenderOptions opt;
            sepal_ports::parse_gl_backend(backend, &opt);
            std::vector<uint8_t> rgba;
            sepal_ports::GlRenderInfo info;
            if (!sepal_ports::render_asset_headless(bytes.data(), bytes.size(), s, opt, &rgba, &info, &err)) return -1.0;
            if (dbl) *dbl = info.stats.doublings;
            return sepal::diff_images(exact, sepal::to_rgb(sepal::image_from_rgba8(rgba.data(), s.width, s.height)), 0).psnr;
        };
        // The reference: the exact render at 4 x 4 samples per pixel; exact_point (the pixel
        // centre only) is reported against it: the reference's own aliasing.
        const int S = sepal::kReferenceSupersample;
        sepal::Image exact, exact_grazing, exact_point;
        if (!sepal::render_exact(*f, def.scene, def.mesh, def.width, def.height, &exact, nullptr, &err, false, S) ||
            !sepal::render_exact(*f, grazing.scene, grazing.mesh, grazing.width, grazing.height, &exact_grazing,
                                 nullptr, &err, false, S) ||
            !sepal::render_exact(*f, def.scene, def.mesh, def.width, def.height, &exact_point, nullptr, &err)) {
            std::fprintf(stderr, "bench: %s: %s\n", m.name, err.c_str());
            ++failures;
            continue;
        }
        exact = clamp8(exact);
        exact_grazing = clamp8(exact_grazing);
        int doublings = 0;
        const double p1 = psnr_asset(bytes, def, exact, "gles1", &doublings);
        const double p2 = psnr_asset(bytes, def, exact, "gles2", nullptr);
        const double pg = psnr_asset(bytes, grazing, exact_grazing, "gles1", nullptr);
        const double pe = sepal::diff_images(exact, clamp8(exact_point), 0).psnr;
        sepal::Image cpu(def.width, def.height, 3);
        double pc = -1;
        if (sepal_ports::render_asset_cpu(bytes.data(), bytes.size(), def, nullptr, &cpu.data, nullptr, &err))
            pc = sepal::diff_images(exact, clamp8(cpu), 0).psnr;
        const sepal::BakeCandidate& w = r.candidates[size_t(r.winner)];
        // The same bake within 8 KB (the size goal): the best image that fits, or none.
        sepal::BakeOptions small = o;
        small.max_bytes = kSmallBytes;
        sepal::BakeResult rs;
        std::vector<uint8_t> small_bytes;
        std::string small_label = "none fits", small_err;
        double p8 = -1;
        if (sepal::bake(*f, small, &rs, &small_err) && sepal::encode_asset(rs.asset, &small_bytes, &small_err)) {
            p8 = psnr_asset(small_bytes, def, exact, "gles1", nullptr);
            small_label = rs.candidates[size_t(rs.winner)].label();
        }
        const char* colour = sepal::colour_name(r.colour);
        std::printf("%-22s %8.2f %8.2f %8.2f %8.2f %8.2f %6d %4d %8zu %7.1f %8.2f %9s  %s | %s\n", m.name, p1, p2, pc, pg,
                    pe, w.passes, doublings, bytes.size(), seconds, p8, colour, w.label().c_str(), small_label.c_str());
        std::fflush(stdout);
        j.begin_object().key("material").value(m.name).key("spec").value(f->spec()).key("issue_table").value(m.issue_table);
        j.key("psnr_gles1").value(p1).key("psnr_gles2").value(p2).key("psnr_cpu").value(pc);
        j.key("psnr_gles1_grazing").value(pg).key("psnr_exact_point").value(pe).key("psnr_judged").value(w.psnr);
        j.key("passes").value(w.passes).key("doublings").value(doublings).key("bytes").value(int64_t(bytes.size()));
        j.key("bake_seconds").value(seconds).key("load_average").value(load).key("winner").value(w.label());
        j.key("white_level").value(r.white).key("diffuse_profile").value(r.diffuse.side > 0);
        j.key("colour").value(colour).key("colour_residual").value(r.colour_residual);
        j.key("small_max_bytes").value(int64_t(kSmallBytes)).key("small_psnr_gles1").value(p8);
        j.key("small_bytes").value(int64_t(small_bytes.size())).key("small_winner").value(small_label).end_object();
        char small_db[32] = "-";
        if (p8 >= 0) std::snprintf(small_db, sizeof small_db, "%.1f", p8);
        char row[640];
        std::snprintf(row, sizeof row, "| %s | %.1f | %.1f | %.1f | %.1f | %.1f | %d | %d | %s | %s | %.1f | %s | %s | %s |\n",
                      m.name, p1, p2, pc, pg, pe, w.passes, doublings, std::to_string(bytes.size()).c_str(), colour,
                      seconds, w.label().c_str(), small_db, small_label.c_str());
        md += row;
    }
    j.end_array().key("load_average_end").value(load_average()).end_object();
    const std::string json = j.str();
    if (!sepal::write_file_atomic(out + "/fidelity.json", json.data(), json.size(), &err) ||
        !sepal::write_file_atomic(out + "/fidelity.md", md.data(), md.size(), &err)) {
        std::fprintf(stderr, "bench: %s\n", err.c_str());
        return 1;
    }
    std::printf("wrote %s/fidelity.json and %s/fidelity.md\n", out.c_str(), out.c_str());
    return failures ? 1 : 0;
}
