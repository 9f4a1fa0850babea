#pragma once
/// \file Phase-function specifications: the JSON object of a scene's "phase" key and the short
/// command-line form. Both go through readPhaseFunction, so they share validation and messages.
///
/// JSON objects (unknown keys are errors; keys without a default are required):
///   {"type": "isotropic"}
///   {"type": "hg", "g": 0.9}                           g ∈ [−0.999999, 0.999999], default 0
///   {"type": "two_term_hg", "g1": 0.9, "g2": -0.3, "w": 0.8}   g1, g2 as g; w ∈ [0, 1]
///   {"type": "rayleigh"}
///   {"type": "schlick", "k": 0.7}                      k ∈ [−0.999999, 0.999999]
///   {"type": "cornette_shanks", "g": 0.8}              g ∈ [−0.999999, 0.999999]
///   {"type": "tabulated", "file": "mie.csv"}           CSV as in phase_table_csv.h
/// "type" defaults to "isotropic". A relative "file" is resolved against the directory of the
/// JSON file (JsonReader::file()).
///
/// SH sampling (any type): "sampling": "sh" wraps the function in an SHSampledPhase, with
///   "order" (bands, 1…256, default 16, or "auto": the lowest order whose relative L2 error is at
///   most "tolerance", default 0.01), "window" ("auto" | "none" | "hann" | "lanczos", default
///   "auto": none unless the unwindowed fit rings negative, then hann), "evaluate" ("sh": the
///   clamped, normalised SH reconstruction is the phase function — default; "exact": the function
///   itself, SH only for the pdf), "sh_depth" (2^depth z-bins, 4…22, default 16). These keys are
///   errors without "sampling": "sh"; "tolerance" is an error without "order": "auto".
///
/// Short form: `name` or `name:key=value,key=value`, e.g. `hg:g=0.9`, `rayleigh`,
/// `two_term_hg:g1=0.9,g2=-0.3,w=0.7`, `tabulated:file=mie.csv`. A value that parses whole as a
/// JSON number is a number, anything else a string (file names). The short form cannot express
/// values containing ',' (or a file whose name is a number); use the JSON form for those.
#include <string>

#include "shvol/io/json_reader.h"
#include "shvol/phase/phase_function.h"

namespace shvol {

/// The SH keys of a phase object, with their defaults ("sampling" itself is not read).
struct SHPhaseKeys {
    ZonalFitRequest fit;
    SHSampledPhase::Evaluate evaluate = SHSampledPhase::Evaluate::Reconstruction;
    int depth = 16;
};
SHPhaseKeys readSHPhaseKeys(JsonReader& r);

/// Reads a phase-function object such as {"type": "hg", "g": 0.9}. Errors name r's file and JSON
/// path, e.g. "scene.json: media[0].phase.g: value 2 out of range [-0.999999, 0.999999]".
PhaseFunction readPhaseFunction(JsonReader r);

/// Reads the phase-function object j; errors name `where` (e.g. `phase spec "hg:g=2"`) and the
/// key; relative table files are resolved against baseDir ("" = the current directory).
PhaseFunction readPhaseFunction(const Json& j, const std::string& where,
                                const std::string& baseDir);

/// How messages name a command line's phase specification: phase spec "SPEC", a long one by its
/// first 77 characters (a 120 kB spec was quoted whole: helper 96).
std::string specName(const std::string& spec);

/// Reads a phase function from either a JSON object string (first non-blank character '{') or
/// the short form above. Relative table files are resolved against baseDir ("" = the current
/// directory). Errors are shvol::Error naming the spec, e.g.
///   phase spec "hg:g=2": g: value 2 out of range [-0.999999, 0.999999]
PhaseFunction parsePhaseSpec(const std::string& spec, const std::string& baseDir);

/// The JSON object a short-form spec stands for ({"type": name, key: value, …}); JSON-object
/// specs are parsed as they are. Errors as for parsePhaseSpec.
Json phaseSpecToJson(const std::string& spec);

}  // namespace shvol
