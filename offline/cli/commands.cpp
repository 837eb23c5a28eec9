// The table of `sepal` subcommands and the dispatcher (CLI11).
#include <algorithm>
#include <cerrno>
#include <cstring>
#include <new>
#include <sstream>

#include <CLI/CLI.hpp>

#include "cli/cli.h"
#include "sepal/sepal_format.h"
#include "sepal/sepal_version.h"

namespace sepal {

const std::vector<Command>& commands() {
    static const std::vector<Command> table = {
        {"diff", "compare two images (PNG or PFM): PSNR, max difference, share over it", setup_diff},
        {"eval", "evaluate a BRDF at one direction pair; prints R G B", setup_eval},
        {"info", "describe a BRDF: parameters, albedo, samples and coverage", setup_info},
        {"gen-merl", "tabulate an isotropic BRDF into a MERL-format .binary file", setup_gen_merl},
        {"factor", "separable factors of a BRDF with the error per number of terms", setup_factor},
        {"bake", "bake a BRDF into a shipping asset: the cheapest candidate meeting the budgets", setup_bake},
        {"bake-scene", "bake the materials a scene lists, each with its budget; skip up-to-date ones",
         setup_bake_scene},
        {"inspect", "validate and print an asset", setup_inspect},
        {"sampler", "an importance sampler for a BRDF (factored, Lawrence 2004, or another kind) and its variance",
         setup_sampler},
        {"fit", "fit a model to scattered samples: lafortune, with each parameter's 95% interval", setup_fit},
        {"measure", "measure: plan, simulate, reconstruct from the MERL database (~800 samples); capture a photograph of the virtual setup",
         setup_measure},
        {"ist", "inverse shade trees: generate an SVBRDF, decompose it into an editable tree, edit, render",
         setup_ist},
        {"render", "render a scene: exact (a BRDF per pixel), or a baked asset on GL ES (headless) or the CPU",
         setup_render},
    };
    return table;
}

CommandRun setup_subcommands(CLI::App& app, const std::vector<Command>& subs) {
    app.require_subcommand(1, 1);
    std::vector<std::pair<const CLI::App*, CommandRun>> runs;
    for (const Command& c : subs) {
        CLI::App* sub = app.add_subcommand(c.name, c.summary);
        runs.emplace_back(sub, c.setup(*sub));
    }
    return [runs](const CommandIO& io) {
        for (const auto& r : runs)
            if (r.first->parsed()) return r.second(io);
        return kExitBadInput;  // require_subcommand makes this unreachable
    };
}

std::string version_line(const char* program) {
    return std::string(program) + " " SEPAL_VERSION_STRING " (asset format " +
           std::to_string(SEPAL_FMT_VERSION_MAJOR) + "." + std::to_string(SEPAL_FMT_VERSION_MINOR) + ")";
}

std::unique_ptr<CLI::App> make_sepal_app(std::vector<CommandRun>* runs) {
    auto app = std::make_unique<CLI::App>(
        "sepal: measured and analytic BRDFs baked into small texture pairs for fixed-function GL ES.\n"
        "'sepal <command> --help' lists a command's flags.",
        "sepal");
    app->set_version_flag("--version", version_line("sepal"));
    app->require_subcommand(1, 1);
    app->get_formatter()->column_width(34);
    runs->clear();
    for (const Command& c : commands()) {
        CLI::App* sub = app->add_subcommand(c.name, c.summary);
        runs->push_back(c.setup(*sub));
    }
    // After the subcommands: CLI11 copies a parent's footer into subcommands added later.
    app->footer(
        "Data: nbrdf:NAME specs read merl-nbrdf/merl-nbrdf.json from $SEPAL_DATA_DIR if set, else from a\n"
        "checkout's data/ or an installed PREFIX/share/sepal/ (found from the executable's folder).\n"
        "'sepal measure --help' says where the measurement database is cached.");
    return app;
}

int run_sepal_args(const std::vector<std::string>& args, const CommandIO& io) {
    std::vector<CommandRun> runs;
    std::unique_ptr<CLI::App> app = make_sepal_app(&runs);
    const bool known = !args.empty() && std::any_of(commands().begin(), commands().end(),
                                                    [&](const Command& c) { return args[0] == c.name; });
    const std::string who = known ? "sepal " + args[0] : "sepal";
    if (args.empty() || args[0] == "help") {
        std::fputs(app->help().c_str(), args.empty() ? io.err : io.out);
        return args.empty() ? kExitBadInput : kExitOk;
    }
    if (known && args.size() > 1 && !args[1].empty() && args[1][0] != '-') {
        // A command made of subcommands (measure): name the ones it has.
        const CLI::App* sub = app->get_subcommand(args[0]);
        const auto subs = sub->get_subcommands([](const CLI::App*) { return true; });
        if (!subs.empty() && std::none_of(subs.begin(), subs.end(), [&](const CLI::App* s) { return s->get_name() == args[1]; })) {
            std::string names;
            for (const CLI::App* s : subs) names += (names.empty() ? "" : ", ") + s->get_name();
            std::fprintf(io.err, "%s: unknown subcommand '%s' (one of %s)\nrun '%s --help' for the accepted flags\n",
                         who.c_str(), args[1].c_str(), names.c_str(), who.c_str());
            return kExitBadInput;
        }
    }
    try {
        std::vector<std::string> reversed(args.rbegin(), args.rend());  // CLI11 takes them last first
        app->parse(reversed);
    } catch (const CLI::CallForHelp&) {
        std::fputs(app->help().c_str(), io.out);  // the selected subcommand's, when there is one
        return kExitOk;
    } catch (const CLI::CallForAllHelp&) {
        std::fputs(app->help("", CLI::AppFormatMode::All).c_str(), io.out);
        return kExitOk;
    } catch (const CLI::CallForVersion&) {
        std::fprintf(io.out, "%s\n", version_line("sepal").c_str());
        return kExitOk;
    } catch (const CLI::ParseError& e) {
        // What went wrong, the usage line, and where the whole list is.
        std::string usage;
        const CLI::App* sub = known ? app->get_subcommand(args[0]) : app.get();
        if (auto f = std::dynamic_pointer_cast<CLI::Formatter>(sub->get_formatter()))
            usage = f->make_usage(sub, who);  // ends with a newline
        std::fprintf(io.err, "%s: %s\n%srun '%s --help' for the accepted flags\n", who.c_str(), e.what(),
                     usage.c_str(), who.c_str());
        return kExitBadInput;
    }
    for (size_t i = 0; i < commands().size(); ++i)
        if (app->got_subcommand(commands()[i].name)) {
            // The tool boundary: an allocation that fails past every estimate is a message and
            // exit 2, not an abort (outputs are written atomically, so none is half done).
            try {
                const int code = runs[i](io);
                // What a command printed must have arrived (sepal info > /dev/full): a write
                // error is an error, whatever the command decided.
                const bool flushed = std::fflush(io.out) == 0;
                const int why = errno;
                if (flushed && !std::ferror(io.out)) return code;
                std::fprintf(io.err, "%s: cannot write its output: %s\n", who.c_str(),
                             flushed ? "write error" : std::strerror(why));
                return kExitBadInput;
            } catch (const std::bad_alloc&) {
                // The hint names only the flags the command that ran has.
                CLI::App* ran = app->get_subcommand(commands()[i].name);
                while (ran && !ran->get_subcommands().empty()) ran = ran->get_subcommands()[0];
                std::string flags;
                for (const char* f : {"--res", "--terms", "--size", "--max-pixels"})
                    if (ran && ran->get_option_no_throw(f)) flags += std::string(flags.empty() ? "" : ", ") + f;
                std::fprintf(io.err, "%s: out of memory (a larger input or setting than this machine can hold%s%s)\n",
                             who.c_str(), flags.empty() ? "" : "; lower ", flags.c_str());
                return kExitBadInput;
            }
        }
    return kExitBadInput;  // require_subcommand makes this unreachable
}

int run_sepal(int argc, char** argv, const CommandIO& io) {
    return run_sepal_args(std::vector<std::string>(argv + 1, argv + argc), io);
}

int run_command(const std::string& name, const std::vector<std::string>& args, const CommandIO& io) {
    std::vector<std::string> all = {name};
    all.insert(all.end(), args.begin(), args.end());
    return run_sepal_args(all, io);
}

}  // namespace sepal
