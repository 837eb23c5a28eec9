// Command-line plumbing shared by sepal's subcommands (offline/cli/commands.cpp).
//
// Each subcommand is a function taking its arguments and two streams and returning the
// process exit code, so tests can run it in-process:
//   0 success, 1 a check failed (e.g. a tolerance), 2 bad usage or unreadable input.
#pragma once
#include <cstdio>
#include <map>
#include <string>
#include <vector>

namespace sepal {

constexpr int kExitOk = 0, kExitCheckFailed = 1, kExitBadInput = 2;

struct CommandIO {
    FILE* out = stdout;
    FILE* err = stderr;
};

using CommandFn = int (*)(const std::vector<std::string>& args, const CommandIO& io);

struct Command {
    const char* name;
    const char* usage;    // one line of arguments
    const char* summary;  // one line
    CommandFn run;
};

// The table of subcommands (commands.cpp).
const std::vector<Command>& commands();
// Dispatches argv (argv[1] is the subcommand); the whole of `sepal`'s main.
int run_sepal(int argc, char** argv, const CommandIO& io = CommandIO{});

// Minimal option parser: `--name value` options from a known list, `--flag` switches,
// the rest positional. Unknown options and missing values are errors.
class Args {
  public:
    Args(const std::vector<std::string>& args, const std::vector<std::string>& valued,
         const std::vector<std::string>& switches = {});
    bool ok() const { return error_.empty(); }
    const std::string& error() const { return error_; }
    const std::vector<std::string>& positional() const { return positional_; }
    bool has(const std::string& name) const;
    std::string get(const std::string& name, const std::string& fallback = "") const;
    // Parses a finite number; on failure sets error() and returns false.
    bool number(const std::string& name, double* value);
    bool integer(const std::string& name, long* value);

  private:
    std::map<std::string, std::string> values_;
    std::vector<std::string> positional_;
    std::string error_;
};

// Subcommands.
int cmd_diff(const std::vector<std::string>& args, const CommandIO& io);
int cmd_eval(const std::vector<std::string>& args, const CommandIO& io);
int cmd_info(const std::vector<std::string>& args, const CommandIO& io);
int cmd_gen_merl(const std::vector<std::string>& args, const CommandIO& io);
int cmd_factor(const std::vector<std::string>& args, const CommandIO& io);
int cmd_render(const std::vector<std::string>& args, const CommandIO& io);
int cmd_bake(const std::vector<std::string>& args, const CommandIO& io);
int cmd_inspect(const std::vector<std::string>& args, const CommandIO& io);
int cmd_bake_scene(const std::vector<std::string>& args, const CommandIO& io);
int cmd_measure(const std::vector<std::string>& args, const CommandIO& io);

}  // namespace sepal
