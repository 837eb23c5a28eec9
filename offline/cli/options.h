// Flag helpers for sepal's commands over CLI11 (Debian libcli11-dev): the sepal types as
// option values, and number checks that refuse NaN and inf.
//
// Usage (inside a setup_<name>, see cli.h):
//   app.add_option("--param", o.params, "parameterizations to try")
//       ->delimiter(',')->transform(param_names())->capture_default_str();
//   app.add_option("--res", o.res, "texels per side")->check(finite_range(1, 256));
//
// Param, HemiMap, Method and ColourMode print by their names (param_name() ...), so CLI11
// shows defaults by name; CLI11 converts enums from integers, so param_names() and friends
// check a name and rewrite it into its enumerator's value (use them with ->transform on every enum option).
// finite_range: CLI11's Range lets "nan" through (every comparison with NaN is false);
// this one refuses non-finite values and says what is accepted.
#pragma once
#include <iosfwd>
#include <string>

#include <CLI/CLI.hpp>

#include "factor/factor.h"
#include "factor/param.h"
#include "bake/image_score.h"

namespace sepal {

std::ostream& operator<<(std::ostream& out, Param p);
std::ostream& operator<<(std::ostream& out, HemiMap m);
std::ostream& operator<<(std::ostream& out, Method m);
std::ostream& operator<<(std::ostream& out, ColourMode c);
std::ostream& operator<<(std::ostream& out, Target t);

// Checks naming the accepted values (shown in --help and in the error).
CLI::Validator param_names();
CLI::Validator map_names();
CLI::Validator method_names();
CLI::Validator colour_names();
CLI::Validator target_names();
// A finite number in [lo, hi] (integers too: "1.5" for an int flag fails conversion later).
CLI::Validator finite_range(double lo, double hi);
// A finite number > 0.
CLI::Validator positive();

}  // namespace sepal
