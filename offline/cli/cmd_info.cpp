// sepal info SPEC|ASSET [--samples N] | sepal info --models: describe a BRDF or list the models.
#include "bake/asset_brdf.h"
#include "brdf/brdf.h"
#include "spec/spec.h"
#include "brdf/brdf_models.h"
#include "brdf/brdf_spec.h"
#include "brdf/brdf_util.h"
#include "cli/cli.h"
#include "cli/options.h"
#include "util/io.h"
#include "util/parallel.h"
#include "util/progress.h"

#include <unistd.h>

namespace sepal {
namespace {

struct InfoArgs {
    std::string spec;
    int samples = 128;
    bool models = false;
};

int run_info(const InfoArgs& a, const CommandIO& io) {
    if (a.models) {
        std::fprintf(io.out, "%s", analytic_models_help().c_str());
        return kExitOk;
    }
    std::string err;
    // An asset is described as the BRDF it represents (bake/asset_brdf.h): its albedo
    // beside its source's (`sepal info SOURCE`) says what the bake kept.
    std::unique_ptr<Brdf> f =
        file_extension(a.spec) == "sepal" ? AssetBrdf::load(a.spec, &err) : make_brdf(a.spec, &err);
    if (!f) {
        std::fprintf(io.err, "sepal info: %s\n", err.c_str());
        return kExitBadInput;
    }
    std::fprintf(io.out, "model              %s\n", f->model().c_str());
    std::fprintf(io.out, "spec               %s\n", f->spec().c_str());
    std::fprintf(io.out, "isotropic          %s\n", f->isotropic() ? "yes" : "no");
    std::fprintf(io.out, "energy conserving  %s\n", f->energy_conserving() ? "yes" : "not claimed");
    std::string info = f->info();
    if (!info.empty() && info.back() != '\n') info += '\n';
    std::fprintf(io.out, "%s", info.c_str());
    std::fprintf(io.out, "directional albedo R G B (quadrature samples %d):\n", a.samples);
    // Each albedo is a 2D quadrature of up to samples^2 / 2 evaluations: seconds for the
    // costlier models (poulin-fournier: ~3.7 s in all on one core), hence the threads and the
    // progress line on a terminal.
    struct Row {
        double theta, phi;
        glm::dvec3 v;
    };
    std::vector<Row> rows;
    for (double phi : {0.0, 90.0}) {
        if (phi != 0.0 && f->isotropic()) break;
        for (double theta : {0.0, 30.0, 60.0, 80.0}) rows.push_back({theta, phi, glm::dvec3(0.0)});
    }
    {
        Progress progress(isatty(fileno(io.err)) != 0, "sepal info: albedo", rows.size());
        parallel_for(rows.size(), 0, [&](size_t i) {
            rows[i].v = directional_albedo(*f, deg2rad(rows[i].theta), a.samples, deg2rad(rows[i].phi));
            progress.advance();
        });
    }
    for (const Row& r : rows)
        std::fprintf(io.out, "  theta_i %2.0f phi_i %2.0f deg: %.6f %.6f %.6f\n", r.theta, r.phi, r.v.x, r.v.y, r.v.z);
    return kExitOk;
}

}  // namespace

CommandRun setup_info(CLI::App& app) {
    auto a = std::make_shared<InfoArgs>();
    CLI::Option* spec =
        app.add_option("SPEC", a->spec,
                       "BRDF spec (model:param=value,...), measured file, or a .sepal asset (the BRDF it represents)");
    CLI::Option* models = app.add_flag("--models", a->models, "list the analytic models and their parameters");
    spec->excludes(models);
    app.add_option("--samples", a->samples, "quadrature samples per albedo")
        ->check(CLI::Range(8, 4096))
        ->capture_default_str();
    app.callback([spec, models] {
        if (!*spec && !*models) throw CLI::RequiredError("SPEC (or --models)");
    });
    return [a](const CommandIO& io) { return run_info(*a, io); };
}

}  // namespace sepal
