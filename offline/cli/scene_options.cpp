#include "cli/scene_options.h"

#include <string>
#include <vector>

namespace sepal {

void add_scene_options(CLI::App& app, sepal_ports::SceneSetup* s) {
    struct Flag {
        const char* name;
        const char* help;
    };
    static const Flag kFlags[] = {
        {"--size", "image size WxH (default 512x512)"},
        {"--mesh", "sphere (default), torus, wave, or PATH.obj"},
        {"--camera", "eye position X,Y,Z (default 0,-3.2,1.4)"},
        {"--target", "look-at point X,Y,Z (default 0,0,0)"},
        {"--fov", "vertical field of view, degrees (default 38)"},
        {"--background", "linear background colour R,G,B (default 0,0,0)"},
    };
    // Through parse_scene_flag, so the checks and messages are the hand parser's.
    auto apply = [s](const std::string& flag, const std::string& value) {
        std::string err;
        std::vector<char*> argv = {const_cast<char*>(flag.c_str()), const_cast<char*>(value.c_str())};
        if (sepal_ports::parse_scene_flag(2, argv.data(), 0, s, &err) < 0) throw CLI::ValidationError(err);
    };
    for (const Flag& f : kFlags) {
        const std::string name = f.name;
        app.add_option_function<std::string>(name, [apply, name](const std::string& v) { apply(name, v); }, f.help)
            ->group("Scene");
    }
    app.add_option_function<std::vector<std::string>>(
           "--light",
           [apply](const std::vector<std::string>& lights) {
               for (const std::string& l : lights) apply("--light", l);
           },
           "point:X,Y,Z[:I|:R,G,B] or dir:X,Y,Z[:I|:R,G,B] (towards the light); repeat for up to 8; "
           "default point:2,-2.5,3:60")
        ->allow_extra_args(false)  // one value per --light: the next word may be the positional
        ->group("Scene");
}

}  // namespace sepal
