// The table of `sepal` subcommands and the dispatcher.
#include <cstring>

#include "cli/cli.h"

namespace sepal {

const std::vector<Command>& commands() {
    static const std::vector<Command> table = {
        {"diff", "A B [--max-diff N] [--max-share P] [--min-psnr D] [--heatmap out.png]",
         "compare two images (PNG or PFM): PSNR, max difference, share over it", cmd_diff},
        {"eval", "SPEC theta_i phi_i theta_o phi_o   (degrees)",
         "evaluate a BRDF at one direction pair; prints R G B", cmd_eval},
        {"info", "SPEC", "describe a BRDF: parameters, albedo, samples and coverage", cmd_info},
        {"gen-merl", "SPEC -o out.binary",
         "tabulate any BRDF into a MERL-format .binary file", cmd_gen_merl},
        {"factor",
         "SPEC [--param P] [--map M] [--res N] [--terms K] [--method M] [--report r.json] "
         "[--plot p.png] [--export DIR]",
         "separable factors of a BRDF with the error per number of terms", cmd_factor},
        {"bake",
         "SPEC -o out.sepal [--param P,..] [--map M,..] [--res N,..] [--terms K,..] [--method M,..] "
         "[--colour rgb|luminance] [--bits 8|16] [--max-error E] [--max-passes P] [--max-bytes B] "
         "[--cap F] [--report r.json] [--export DIR] [--threads N]",
         "bake a BRDF into a shipping asset: the cheapest candidate meeting the budgets", cmd_bake},
        {"bake-scene", "scene.json -o DIR [--threads N] [--force]",
         "bake the materials a scene lists, each with its budget; skip up-to-date ones", cmd_bake_scene},
        {"inspect", "FILE.sepal", "validate and print an asset", cmd_inspect},
        {"measure", "plan|simulate|reconstruct ...",
         "measure a material with ~800 samples: plan, simulate, reconstruct from the MERL database",
         cmd_measure},
        {"render",
         "SPEC_OR_ASSET --backend exact|gles1|gles2|gles2-fused|gles2-fused-pixel|cpu [--mask LIST] "
         "[--diffuse PNG] [--float-target] [scene flags] -o out.png [--float out.pfm]",
         "render a scene: exact (a BRDF per pixel), or a baked asset on GL ES (headless) or the CPU",
         cmd_render},
    };
    return table;
}

static void usage(FILE* f) {
    std::fprintf(f, "usage: sepal <command> [arguments]\n\ncommands:\n");
    for (const Command& c : commands()) std::fprintf(f, "  %-10s %s\n", c.name, c.summary);
    std::fprintf(f, "\n'sepal <command> --help' shows a command's arguments.\n");
}

int run_sepal(int argc, char** argv, const CommandIO& io) {
    if (argc < 2) {
        usage(io.err);
        return kExitBadInput;
    }
    const char* name = argv[1];
    if (!std::strcmp(name, "help") || !std::strcmp(name, "--help") || !std::strcmp(name, "-h")) {
        usage(io.out);
        return kExitOk;
    }
    for (const Command& c : commands()) {
        if (std::strcmp(c.name, name) != 0) continue;
        std::vector<std::string> args(argv + 2, argv + argc);
        if (!args.empty() && (args[0] == "--help" || args[0] == "-h")) {
            std::fprintf(io.out, "usage: sepal %s %s\n  %s\n", c.name, c.usage, c.summary);
            return kExitOk;
        }
        return c.run(args, io);
    }
    std::fprintf(io.err, "sepal: unknown command '%s'\n", name);
    usage(io.err);
    return kExitBadInput;
}

}  // namespace sepal
