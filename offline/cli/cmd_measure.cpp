// sepal measure: measuring a material with a few hundred samples instead of 1.5 million
// (Matusik et al. 2003, section 7; offline/database/). Subcommands:
//   sepal measure plan --samples N -o plan.json [--method greedy|picture|random|uniform] [--seed S]
//                      [--space log|linear] [--objective prediction|condition]
//                      [--exclude NAME,..] [--swaps N] [--candidates N] [--picture-swaps N] [--materials NAME,..]
//   sepal measure simulate SPEC plan.json -o samples.csv [--noise 0.01] [--seed S] [--materials ..]
//   sepal measure reconstruct plan.json samples.csv -o new.binary [--exclude NAME,..]
//                      [--space log|linear] [--solver ls|nnls] [--max-condition K] [--truth SPEC]
//                      [--report r.json]
//                      [--bake out.sepal] [--materials ..]
// The database (the 100 merl-nbrdf materials on the MERL grid) is built on first use into the
// cache (database.h: about a minute, 1.4 GB) and memory-mapped afterwards. --materials limits
// it to a subset (a smaller, faster database; tests use it). A new subcommand (as `capture`)
// is one more subcommand in setup_measure.
//   sepal measure capture -o photo.png [--samples s.csv] [--object sphere|torus|wave]
//                      [--camera AZ,EL] [--light AZ,EL] [--seed S] [--no-noise]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>


#include "bake/asset_file.h"
#include "bake/bake.h"
#include "brdf/brdf.h"
#include "spec/spec.h"
#include "cli/cli.h"
#include "cli/options.h"
#include "cli/picture_report.h"
#include "database/database.h"
#include "database/linear_model.h"
#include "database/measure.h"
#include "database/measure_plan.h"
#include "acquire/capture.h"
#include "acquire/object.h"
#include "acquire/known.h"
#include "measured/samples.h"
#include "util/image.h"
#include "measured/merl.h"
#include "util/io.h"
#include "util/json.h"

namespace sepal {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

// The database every subcommand works on (progress on stderr while it is built).
std::unique_ptr<BrdfDatabase> open_database(const std::string& who, const std::vector<std::string>& materials,
                                            const CommandIO& io) {
    std::string err;
    auto set = load_default_nbrdf_set(&err);
    if (!set) {
        std::fprintf(io.err, "%s: %s\n", who.c_str(), err.c_str());
        return nullptr;
    }
    DatabaseOptions o;
    o.materials = materials;
    o.progress = io.err;
    auto db = BrdfDatabase::open(*set, o, &err);
    if (!db) std::fprintf(io.err, "%s: %s\n", who.c_str(), err.c_str());
    return db;
}

struct PlanArgs {
    int samples = 800;
    std::string out, method = "picture", space = "log", objective = "prediction";
    uint64_t seed = 1;
    int swaps = 400;
    int candidates = 32;
    int picture_swaps = 2000;
    std::vector<std::string> exclude, materials;
};

int run_plan(const PlanArgs& a, const CommandIO& io) {
    const std::string who = "sepal measure plan";
    PlanOptions o;
    if (!parse_plan_method(a.method, &o.method)) {
        std::fprintf(io.err, "%s: --method '%s': accepted greedy, picture, random, uniform\n", who.c_str(), a.method.c_str());
        return kExitBadInput;
    }
    auto db = open_database(who, a.materials, io);
    if (!db) return kExitBadInput;
    std::string err;
    if (!exclude_mask(*db, a.exclude, &o.use, &err)) {
        std::fprintf(io.err, "%s: %s\n", who.c_str(), err.c_str());
        return kExitBadInput;
    }
    o.samples = a.samples;
    o.seed = a.seed;
    o.max_swaps = a.swaps;
    o.candidates = a.candidates;
    o.picture_swaps = a.picture_swaps;
    o.progress = io.err;  // picture: a line per 500 swaps (a minute's work)
    o.space = a.space == "linear" ? FitSpace::kLinear : FitSpace::kLog;
    o.objective = a.objective == "condition" ? PlanObjective::kCondition : PlanObjective::kPrediction;
    const auto t0 = Clock::now();
    MeasurementPlan plan;
    if (!plan_measurement(*db, o, &plan, &err) || !write_plan_json(a.out, *db, plan, &err)) {
        std::fprintf(io.err, "%s: %s\n", who.c_str(), err.c_str());
        return kExitBadInput;
    }
    const double t = seconds_since(t0);
    std::fprintf(io.out, "plan       %s, %zu samples (direction pair + channel), %d database materials%s\n",
                 plan_method_name(plan.method), plan.rows.size(), db->size() - int(plan.excluded.size()),
                 plan.excluded.empty() ? "" : " (some excluded)");
    std::fprintf(io.out, "condition  %.4g (of the %s model's column-normalised X^T X)", plan.condition,
                 fit_space_name(o.space));
    if (plan.method != PlanMethod::kRandom) {
        PlanOptions r = o;
        r.method = PlanMethod::kRandom;
        MeasurementPlan rp;
        if (plan_measurement(*db, r, &rp, &err))
            std::fprintf(io.out, "; a random plan of the same size: %.4g (%.1fx)", rp.condition,
                         rp.condition / plan.condition);
    }
    std::fprintf(io.out, "\n");
    if (plan.method == PlanMethod::kGreedy && o.objective == PlanObjective::kCondition)
        std::fprintf(io.out, "greedy     forward pass %.4g, %d condition-number swaps, %.1f s\n",
                     plan.condition_forward, plan.swaps, t);
    else if (plan.method == PlanMethod::kGreedy)
        std::fprintf(io.out, "greedy     mean prediction variance over the pool, %.1f s\n", t);
    else if (plan.method == PlanMethod::kPicture)
        std::fprintf(io.out,
                     "picture    the best of %d random plans by the database's leave-one-out pictures, then %d of %d row "
                     "swaps kept: %.2f dB mean, %.1f s\n",
                     o.candidates, plan.swaps, o.picture_swaps, plan.picture_db, t);
    std::fprintf(io.out, "wrote      %s\n", a.out.c_str());
    return kExitOk;
}

struct SimulateArgs {
    std::string spec, plan, out;
    double noise = 0.0;
    uint64_t seed = 1;
    std::vector<std::string> materials;
};

int run_simulate(const SimulateArgs& a, const CommandIO& io) {
    const std::string who = "sepal measure simulate";
    std::string err;
    if (!(a.noise >= 0.0 && a.noise <= 1.0)) {
        std::fprintf(io.err, "%s: --noise %g: accepted 0 .. 1 (a relative standard deviation)\n", who.c_str(), a.noise);
        return kExitBadInput;
    }
    std::unique_ptr<Brdf> f = make_brdf(a.spec, &err);
    if (!f) {
        std::fprintf(io.err, "%s: %s\n", who.c_str(), err.c_str());
        return kExitBadInput;
    }
    auto db = open_database(who, a.materials, io);
    if (!db) return kExitBadInput;
    MeasurementPlan plan;
    std::vector<double> v;
    char comment[512];
    std::snprintf(comment, sizeof comment, "%s, plan %s, noise %g, seed %llu", f->spec().c_str(),
                  a.plan.c_str(), a.noise, (unsigned long long)a.seed);
    if (!read_plan_json(a.plan, *db, &plan, &err) || !simulate_samples(*db, plan, *f, a.noise, a.seed, &v, &err) ||
        !write_samples_csv(a.out, *db, plan, v, comment, &err)) {
        std::fprintf(io.err, "%s: %s\n", who.c_str(), err.c_str());
        return kExitBadInput;
    }
    if (!f->isotropic())
        std::fprintf(io.err, "%s: warning: %s is anisotropic; the instrument measures its phi_h = 0 slice\n",
                     who.c_str(), f->spec().c_str());
    std::fprintf(io.out, "simulated  %zu samples of %s (noise %g), wrote %s\n", v.size(), f->spec().c_str(),
                 a.noise, a.out.c_str());
    return kExitOk;
}

struct ReconstructArgs {
    std::string plan, samples, out, space = "log", solver = "nnls", truth, report, bake;
    double max_condition = FitOptions{}.max_condition;
    std::vector<std::string> exclude, materials;
};

// --truth: the reconstruction against the true BRDF, by its picture first (bake/picture.h: the
// default scene and the held-out conditions, exact renders), then over the grid's cells.
bool truth_figures(const BrdfDatabase& db, const Brdf& truth, const DatabaseReconstruction& r, Json* report,
                   const CommandIO& io, std::string* err) {
    std::vector<float> tv;
    if (!tabulate_rows(db, truth, &tv, err)) return false;
    std::unique_ptr<Brdf> rb = rows_brdf(db, r.values, "reconstruction", err);
    Json picture;
    if (!rb || !report_picture(truth, *rb, io.out, &picture, err)) return false;
    const double e = relative_rms(r.values, tv);
    std::fprintf(io.out, "error      %.2f%% relative RMS against %s over the %zu grid cells above the horizon\n",
                 100 * e, truth.spec().c_str(), db.valid_cells());
    (*report)["truth"] = truth.spec();
    (*report)["picture"] = picture;
    (*report)["relative_rms_vs_truth"] = e;
    return true;
}

int run_reconstruct(const ReconstructArgs& a, const CommandIO& io) {
    const std::string who = "sepal measure reconstruct";
    FitOptions fo;
    if (a.solver == "ls") {
        fo.solver = Solver::kLeastSquares;
    } else if (a.solver == "nnls") {
        fo.solver = Solver::kNonNegative;
    } else {
        std::fprintf(io.err, "%s: --solver '%s': accepted ls, nnls\n", who.c_str(), a.solver.c_str());
        return kExitBadInput;
    }
    if (!(a.max_condition >= 2.0 && a.max_condition <= 1e15)) {
        std::fprintf(io.err, "%s: --max-condition %g: accepted 2 .. 1e15\n", who.c_str(), a.max_condition);
        return kExitBadInput;
    }
    fo.max_condition = a.max_condition;
    fo.space = a.space == "linear" ? FitSpace::kLinear : FitSpace::kLog;
    std::string err;
    if (!check_output("-o", a.out, &err) || !check_output("--report", a.report, &err) ||
        !check_output("--bake", a.bake, &err)) {
        std::fprintf(io.err, "%s: %s\n", who.c_str(), err.c_str());
        return kExitBadInput;
    }
    std::unique_ptr<Brdf> truth;
    if (!a.truth.empty() && !(truth = make_brdf(a.truth, &err))) {
        std::fprintf(io.err, "%s: --truth: %s\n", who.c_str(), err.c_str());
        return kExitBadInput;
    }
    auto db = open_database(who, a.materials, io);
    if (!db) return kExitBadInput;
    const auto t0 = Clock::now();
    MeasurementPlan plan;
    std::vector<double> v;
    if (!read_plan_json(a.plan, *db, &plan, &err) || !read_samples_csv(a.samples, *db, plan, &v, &err)) {
        std::fprintf(io.err, "%s: %s\n", who.c_str(), err.c_str());
        return kExitBadInput;
    }
    // The model: every database material but those excluded here or by the plan.
    std::vector<std::string> excluded = a.exclude;
    for (const std::string& n : plan.excluded) excluded.push_back(n);
    std::vector<uint8_t> use;
    DatabaseReconstruction r;
    if (!exclude_mask(*db, excluded, &use, &err) || !reconstruct(*db, plan, v, use, fo, &r, &err)) {
        std::fprintf(io.err, "%s: %s\n", who.c_str(), err.c_str());
        return kExitBadInput;
    }
    if (!db->grid().is_merl() || !write_reconstruction_merl(a.out, *db, r, &err)) {
        std::fprintf(io.err, "%s: %s\n", who.c_str(), err.empty() ? "the database grid is not MERL's" : err.c_str());
        return kExitBadInput;
    }
    const double t = seconds_since(t0);
    int used = 0;
    for (uint8_t u : use) used += u;
    if (fo.space == FitSpace::kLog)
        std::fprintf(io.out, "model      log-space combination of %d database materials and a colour scale "
                     "(cosine-weighted least squares, max condition %.3g)\n", used, fo.max_condition);
    else
        std::fprintf(io.out, "model      linear combination of %d database materials (%s, max condition %.3g)\n",
                     used, a.solver == "ls" ? "least squares" : "non-negative least squares", fo.max_condition);
    std::fprintf(io.out, "fit        %zu samples, condition %.4g, lambda %.3g, residual on the samples %.2f%%, "
                 "%d nonzero coefficients\n",
                 v.size(), r.fit.condition, r.fit.lambda, 100 * r.fit.sample_rms, r.fit.nonzero);
    if (r.clamped)
        std::fprintf(io.out, "clamped    %zu of %zu values below 0 set to 0\n", r.clamped, r.values.size());
    Json report;
    report["plan"] = a.plan;
    report["samples"] = a.samples;
    report["excluded"] = excluded;
    report["space"] = fit_space_name(fo.space);
    if (fo.space == FitSpace::kLinear) report["solver"] = a.solver;
    report["max_condition"] = fo.max_condition;
    report["condition_number"] = r.fit.condition;
    report["lambda"] = r.fit.lambda;
    report["sample_relative_rms"] = r.fit.sample_rms;
    report["clamped_values"] = r.clamped;
    Json coeffs = Json::object();
    for (int k = 0; k < db->size(); ++k)
        if (r.fit.coeffs[size_t(k)] != 0.0) coeffs[db->name(k)] = r.fit.coeffs[size_t(k)];
    report["coefficients"] = coeffs;
    if (fo.space == FitSpace::kLog)
        report["channel_offsets"] = {r.fit.offsets[0], r.fit.offsets[1], r.fit.offsets[2]};
    if (truth && !truth_figures(*db, *truth, r, &report, io, &err)) {
        std::fprintf(io.err, "%s: --truth: %s\n", who.c_str(), err.c_str());
        return kExitBadInput;
    }
    report["seconds"] = t;
    std::fprintf(io.out, "wrote      %s (MERL .binary, %.1f s)\n", a.out.c_str(), t);
    if (!a.report.empty()) {
        const std::string text = report.dump(1) + "\n";
        if (!write_file_atomic(a.report, text.data(), text.size(), &err)) {
            std::fprintf(io.err, "%s: %s\n", who.c_str(), err.c_str());
            return kExitBadInput;
        }
    }
    if (!a.bake.empty()) {
        std::unique_ptr<Brdf> f = load_merl_brdf(a.out, &err);
        BakeResult br;
        if (!f || !bake(*f, BakeOptions{}, &br, &err) || !write_asset(a.bake, br.asset, &err)) {
            std::fprintf(io.err, "%s: --bake: %s\n", who.c_str(), err.c_str());
            return kExitBadInput;
        }
        std::fprintf(io.out, "baked      %s with the default search (sepal bake %s ... for other budgets)\n",
                     a.bake.c_str(), a.out.c_str());
    }
    return kExitOk;
}

// sepal measure capture: one photograph of the virtual acquisition setup (Lensch et al. 2003;
// offline/acquire/): a known object with a known SVBRDF, a camera and a point light placed by
// azimuth and elevation, shadows and sensor noise; the PNG and, per measuring pixel, its
// sample (local directions, value, weight, pixel and atlas texel) for `sepal fit lafortune`.
struct CaptureArgs {
    std::string object = "sphere", out, samples;
    int atlas = 128, size = 256;
    std::vector<double> camera = {-90, 30}, light = {-50, 45};
    uint64_t seed = 1;
    bool no_noise = false;
};

int run_capture(const CaptureArgs& a, const CommandIO& io) {
    const std::string who = "sepal measure capture";
    auto fail = [&](const std::string& m) {
        std::fprintf(io.err, "%s: %s\n", who.c_str(), m.c_str());
        return kExitBadInput;
    };
    std::string err;
    if (!check_output("-o", a.out, &err) || !check_output("--samples", a.samples, &err)) return fail(err);
    AcqObject obj;
    BlendSvbrdf truth;
    const RigOptions rig;
    if (!make_object(a.object, a.atlas, &obj, &err) || !make_svbrdf(a.atlas, SvbrdfGenOptions(), &truth, &err))
        return fail(err);
    const ViewPair v = view_from_angles(a.camera[0], a.camera[1], a.light[0], a.light[1]);
    if (separation_deg(v) < rig.min_separation_deg)
    {
        char m[160];
        std::snprintf(m, sizeof m, "--camera and --light are %.1f degrees apart; the rig needs at least %g",
                      separation_deg(v), rig.min_separation_deg);
        return fail(m);
    }
    RenderSvbrdfOptions ro;
    ro.shadows = true;
    ro.noise = !a.no_noise;
    ro.seed = a.seed;
    ro.rig = &rig;
    Image img;
    std::vector<PhotoSample> photo;
    if (!render_svbrdf(obj, truth, scene_for_view(obj, v, rig), a.size, a.size, ro, &img, &err, &photo))
        return fail(err);
    std::vector<BrdfSample> s_out(photo.size());
    std::vector<std::vector<double>> extra(3, std::vector<double>(photo.size()));
    for (size_t i = 0; i < photo.size(); ++i) {
        s_out[i].wi = glm::dvec3(photo[i].wi);
        s_out[i].wo = glm::dvec3(photo[i].wo);
        s_out[i].value = glm::dvec3(photo[i].value);
        s_out[i].weight = photo[i].weight;
        extra[0][i] = photo[i].x, extra[1][i] = photo[i].y, extra[2][i] = photo[i].texel;
    }
    char comment[256];
    std::snprintf(comment, sizeof comment, "sepal measure capture: %s, camera %g,%g light %g,%g (azimuth, elevation), seed %llu",
                  a.object.c_str(), a.camera[0], a.camera[1], a.light[0], a.light[1], (unsigned long long)a.seed);
    OutputGuard written;  // both files or neither
    if (!a.samples.empty()) {
        if (!write_brdf_samples(a.samples, s_out, comment, &err, {"x", "y", "texel"}, extra)) return fail(err);
    }
    if (!write_png(a.out, img, &err) || !written.commit(&err)) return fail(err);
    std::fprintf(io.out, "object     %s, atlas %dx%d, the default SVBRDF (%zu materials)\n", a.object.c_str(), a.atlas,
                 a.atlas, default_svbrdf_materials().size());
    std::fprintf(io.out, "view       camera %g,%g light %g,%g (azimuth, elevation; %.1f degrees apart)\n", a.camera[0],
                 a.camera[1], a.light[0], a.light[1], separation_deg(v));
    std::fprintf(io.out, "samples    %zu pixels measure a sample (seen, lit, within %g degrees)%s\n", photo.size(),
                 rig.max_angle_deg, a.samples.empty() ? "" : (": " + a.samples).c_str());
    std::fprintf(io.out, "png        %s\n", a.out.c_str());
    return kExitOk;
}

// The subcommands' flags (the run_* functions above hold the work).
const char* const kMaterialsHelp = "limit the database to these merl-nbrdf materials (smaller and faster)";

CommandRun setup_plan(CLI::App& c) {
    auto a = std::make_shared<PlanArgs>();
    c.add_option("--samples", a->samples, "direction pairs to measure")
        ->check(CLI::Range(1, 100000))->capture_default_str();
    c.add_option("-o,--output", a->out, "the plan to write (.json)")->required();
    c.add_option("--method", a->method,
                 "picture (the plan whose leave-one-out pictures of the database are best: the best of --candidates "
                 "random plans, then --picture-swaps row swaps), greedy (see --objective), random or uniform")
        ->check(CLI::IsMember({"greedy", "picture", "random", "uniform"}))->capture_default_str();
    c.add_option("--candidates", a->candidates, "picture: random plans judged")
        ->check(CLI::Range(1, 1024))->capture_default_str();
    c.add_option("--picture-swaps", a->picture_swaps, "picture: row exchanges proposed after the best candidate")
        ->check(CLI::Range(0, 1 << 20))->capture_default_str();

    c.add_option("--space", a->space, "the model the plan is for: log (reconstruct's default) or linear (the paper's)")
        ->check(CLI::IsMember({"log", "linear"}))->capture_default_str();
    c.add_option("--objective", a->objective,
                 "greedy: prediction (mean prediction variance) or condition (the paper's condition number)")
        ->check(CLI::IsMember({"prediction", "condition"}))->capture_default_str();
    c.add_option("--seed", a->seed, "random seed (random plans; picture: the first candidate's; greedy's tie breaks)")->capture_default_str();
    c.add_option("--swaps", a->swaps, "greedy's improving swaps after the first pass")
        ->check(CLI::Range(0, 1 << 20))->capture_default_str();
    c.add_option("--exclude", a->exclude, "materials left out of the database (leave-one-out)")
        ->delimiter(',');
    c.add_option("--materials", a->materials, kMaterialsHelp)->delimiter(',');
    return [a](const CommandIO& io) { return run_plan(*a, io); };
}

CommandRun setup_simulate(CLI::App& c) {
    auto a = std::make_shared<SimulateArgs>();
    c.add_option("SPEC", a->spec, "the BRDF to measure (spec or measured file)")->required();
    c.add_option("PLAN", a->plan, "a plan from `sepal measure plan`")->required();
    c.add_option("-o,--output", a->out, "the samples to write (.csv)")->required();
    c.add_option("--noise", a->noise, "relative Gaussian noise per sample, e.g. 0.01")
        ->check(finite_range(0, 10))->capture_default_str();
    c.add_option("--seed", a->seed, "noise seed")->capture_default_str();
    c.add_option("--materials", a->materials, kMaterialsHelp)->delimiter(',');
    return [a](const CommandIO& io) { return run_simulate(*a, io); };
}

CommandRun setup_reconstruct(CLI::App& c) {
    auto a = std::make_shared<ReconstructArgs>();
    c.add_option("PLAN", a->plan, "the plan the samples follow")->required();
    c.add_option("SAMPLES", a->samples, "measured samples (.csv)")->required();
    c.add_option("-o,--output", a->out, "the reconstruction to write (MERL .binary)")->required();
    c.add_option("--space", a->space, "log (relative, cosine-weighted residuals: renders right) or linear (the paper's)")
        ->check(CLI::IsMember({"log", "linear"}))->capture_default_str();
    c.add_option("--solver", a->solver, "linear space: ls (least squares) or nnls (non-negative weights)")
        ->check(CLI::IsMember({"ls", "nnls"}))->capture_default_str();
    c.add_option("--max-condition", a->max_condition, "regularise fits worse conditioned than this down to it")
        ->check(positive())->capture_default_str();
    c.add_option("--truth", a->truth, "the true BRDF: the reconstruction's picture and grid errors against it");
    c.add_option("--report", a->report, "write the fit and its errors as JSON");
    c.add_option("--bake", a->bake, "also bake the reconstruction with the default search");
    c.add_option("--exclude", a->exclude, "materials left out of the database")->delimiter(',');
    c.add_option("--materials", a->materials, kMaterialsHelp)->delimiter(',');
    return [a](const CommandIO& io) { return run_reconstruct(*a, io); };
}

CommandRun setup_capture(CLI::App& c) {
    auto a = std::make_shared<CaptureArgs>();
    c.add_option("-o,--output", a->out, "the photograph (PNG)")->required();
    c.add_option("--samples", a->samples, "also write the measured samples (.csv, for sepal fit)");
    c.add_option("--object", a->object, "sphere, torus or wave")
        ->check(CLI::IsMember({"sphere", "torus", "wave"}))->capture_default_str();
    c.add_option("--atlas", a->atlas, "the object's texture atlas, texels per side")
        ->check(CLI::Range(8, 1024))->capture_default_str();
    c.add_option("--size", a->size, "photograph side, pixels")->check(CLI::Range(16, 4096))->capture_default_str();
    c.add_option("--camera", a->camera, "camera azimuth,elevation in degrees")
        ->delimiter(',')->expected(2)->check(finite_range(-360, 360))->capture_default_str();
    c.add_option("--light", a->light, "light azimuth,elevation in degrees")
        ->delimiter(',')->expected(2)->check(finite_range(-360, 360))->capture_default_str();
    c.add_option("--seed", a->seed, "sensor noise seed")->capture_default_str();
    c.add_flag("--no-noise", a->no_noise, "a noiseless photograph");
    return [a](const CommandIO& io) { return run_capture(*a, io); };
}

}  // namespace

CommandRun setup_measure(CLI::App& app) {
    app.footer(
        "The database cache (about 1.4 GB, built on first use): $SEPAL_CACHE_DIR/database if set; for an\n"
        "installed sepal $XDG_CACHE_HOME/sepal/database (default ~/.cache/sepal/database); in a build\n"
        "tree build/cache/database.");
    return setup_subcommands(app, {
        {"plan", "choose the sample directions that pin the database model down", setup_plan},
        {"simulate", "measure a known BRDF at a plan's directions (virtual gonioreflectometer)", setup_simulate},
        {"reconstruct", "fit the database model (log space by default) to measured samples", setup_reconstruct},
        {"capture", "photograph the virtual acquisition setup (known object and SVBRDF)", setup_capture},
    });
}

}  // namespace sepal
