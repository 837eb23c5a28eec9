// The command line's numeric flags: the words of the input (one per line) parsed by sepal's
// CLI11 parser (every command's flags, cli/options.h checks; nothing runs) and by the scene
// flags' hand parser (ports/common/scene_flags.h: --size, --camera, --fov, --light, ...).
// Nothing may throw but CLI11's ParseError; an accepted scene flag holds exactly the number
// written (no wraparound), finite.
#include <cmath>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli/cli.h"
#include "common/scene_flags.h"
#include "fuzz/fuzz.h"

namespace {

std::vector<std::string> words(const uint8_t* data, size_t size) {
    std::vector<std::string> out(1);
    for (size_t i = 0; i < size && out.size() <= 24; ++i) {
        if (data[i] == '\n') out.emplace_back();
        else out.back().push_back(char(data[i]));
    }
    return out;
}

void scene_flags(const std::vector<std::string>& args) {
    const char* h = "cli_flags";
    std::vector<std::string> copy = args;
    std::vector<char*> argv;
    for (std::string& w : copy) argv.push_back(&w[0]);
    sepal_ports::SceneSetup s;
    for (int i = 0; i < int(argv.size());) {
        std::string err;
        const int used = sepal_ports::parse_scene_flag(int(argv.size()), argv.data(), i, &s, &err);
        if (used < 0) {
            sepal_fuzz::check(!err.empty(), h, "a scene flag refused without a message");
            return;
        }
        if (used == 0) {
            ++i;
            continue;
        }
        if (args[size_t(i)] == "--size") {  // the value, read as wide as it is written
            const std::string& v = args[size_t(i) + 1];
            sepal_fuzz::check(std::strtoll(v.c_str(), nullptr, 10) == s.width &&
                                  std::strtoll(v.c_str() + v.find('x') + 1, nullptr, 10) == s.height,
                              h, "--size accepted a value other than the one written");
        }
        i += used;
    }
    sepal_fuzz::check(s.width >= 1 && s.width <= 8192 && s.height >= 1 && s.height <= 8192, h, "size out of range");
    const sepal_camera& c = s.scene.camera;
    for (int k = 0; k < 3; ++k)
        sepal_fuzz::check(std::isfinite(c.eye[k]) && std::isfinite(c.target[k]) && s.scene.background[k] >= 0 &&
                              std::isfinite(s.scene.background[k]),
                          h, "a non-finite camera or background");
    sepal_fuzz::check(std::isfinite(c.fovy_degrees), h, "a non-finite fov");
    for (int l = 0; l < s.scene.light_count; ++l)
        for (int k = 0; k < 3; ++k)
            sepal_fuzz::check(std::isfinite(s.scene.lights[l].position[k]) && std::isfinite(s.scene.lights[l].intensity[k]),
                              h, "a non-finite light");
}

}  // namespace

extern "C" int sepal_fuzz_cli_flags(const uint8_t* data, size_t size) {
    const std::vector<std::string> args = words(data, size);
    scene_flags(args);
    static std::vector<sepal::CommandRun> runs;
    std::unique_ptr<CLI::App> app = sepal::make_sepal_app(&runs);
    try {
        std::vector<std::string> reversed(args.rbegin(), args.rend());  // CLI11 takes them last first
        app->parse(reversed);
    } catch (const CLI::ParseError&) {
    }
    return 0;
}
