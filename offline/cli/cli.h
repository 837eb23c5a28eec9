// sepal's command line: the table of subcommands and how each declares its flags (CLI11).
//
// Each subcommand runs in-process with its own streams and returns the exit code, so tests
// call it like the shell does:
//   0 success, 1 a check failed (e.g. a tolerance), 2 bad usage or unreadable input.
//   std::vector<std::string> args = {"lambert", "--res", "16"};
//   int code = sepal::run_command("factor", args, sepal::CommandIO{out_file, err_file});
//
// Adding a command (offline/cli/cmd_foo.cpp):
//   namespace { struct FooArgs { std::string spec; int res = 32; }; }
//   CommandRun setup_foo(CLI::App& app) {
//       auto a = std::make_shared<FooArgs>();
//       app.add_option("SPEC", a->spec, "BRDF spec or measured file")->required();
//       add_int(app, "--res", &a->res, 1, 256, "texels per side");   // cli/options.h
//       return [a](const CommandIO& io) { return run_foo(*a, io); };
//   }
// plus one row in commands.cpp's table. Parsing, `--help` (generated from the declared
// flags: every flag is listed, tests/offline/cli/cli_test.cpp checks), unknown flags and
// bad values are handled once, in run_command: a parse error prints
// "sepal foo: <what>" and "run 'sepal foo --help' ..." on io.err and returns 2.
// `sepal --version` prints SEPAL_VERSION_STRING (runtime/include/sepal/sepal_version.h).
#pragma once
#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace sepal {

constexpr int kExitOk = 0, kExitCheckFailed = 1, kExitBadInput = 2;

struct CommandIO {
    FILE* out = stdout;
    FILE* err = stderr;
};

// What a command does once its flags are parsed.
using CommandRun = std::function<int(const CommandIO& io)>;
// Declares a command's flags on `app`, bound to state the returned CommandRun owns.
using CommandSetup = CommandRun (*)(CLI::App& app);

struct Command {
    const char* name;
    const char* summary;  // one line
    CommandSetup setup;
};

// A command made of subcommands (`sepal measure plan|simulate|...`): each row declares one
// subcommand's flags as a command's setup does; the returned run runs the one parsed.
CommandRun setup_subcommands(CLI::App& app, const std::vector<Command>& subs);

// The table of subcommands (commands.cpp).
const std::vector<Command>& commands();
// `sepal`'s parser: every command a subcommand with its flags declared; (*runs)[i] is
// commands()[i]'s run. For the flag-table test and for run_sepal.
std::unique_ptr<CLI::App> make_sepal_app(std::vector<CommandRun>* runs);
// Parses args (without the program name) and runs the command they name.
int run_sepal_args(const std::vector<std::string>& args, const CommandIO& io);
// The whole of `sepal`'s main.
int run_sepal(int argc, char** argv, const CommandIO& io = CommandIO{});
// Runs one command: run_sepal_args({name, args...}).
int run_command(const std::string& name, const std::vector<std::string>& args, const CommandIO& io);
// "sepal 0.9.0 (asset format 1.0)"
std::string version_line(const char* program);

// Subcommands: setup_<name> declares the flags; run_command(name, ...) parses and runs.
CommandRun setup_diff(CLI::App& app);
CommandRun setup_eval(CLI::App& app);
CommandRun setup_ist(CLI::App& app);
CommandRun setup_info(CLI::App& app);
CommandRun setup_gen_merl(CLI::App& app);
CommandRun setup_factor(CLI::App& app);
CommandRun setup_render(CLI::App& app);
CommandRun setup_bake(CLI::App& app);
CommandRun setup_inspect(CLI::App& app);
CommandRun setup_bake_scene(CLI::App& app);
CommandRun setup_sampler(CLI::App& app);
CommandRun setup_fit(CLI::App& app);
CommandRun setup_measure(CLI::App& app);

}  // namespace sepal
