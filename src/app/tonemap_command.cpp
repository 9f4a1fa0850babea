// shvol tonemap: an 8-bit sRGB PNG preview of a linear EXR.
#include <cstdio>
#include <filesystem>

#include "commands.h"
#include "shvol/core/error.h"
#include "shvol/io/exr.h"
#include "shvol/io/png.h"

namespace shvol::app {

void addTonemapCommand(CLI::App& app, std::function<int()>& run) {
    struct Args {
        std::string input, output;
        double exposure = 0;
    };
    auto a = std::make_shared<Args>();
    CLI::App* c = app.add_subcommand(
        "tonemap", "Write an sRGB PNG preview of an EXR: clamp(2^exposure * v), sRGB-encoded");
    c->add_option("image", a->input, "Input EXR")->required()->check(nonEmptyName());
    c->add_option("-o,--output", a->output, "Output PNG")
        ->required()
        ->check(outputNamed(".png", "tonemap writes PNG"));
    c->add_option("--exposure", a->exposure, "Exposure in stops (default 0)")
        ->check(numberIn(-64.0, 64.0, false, " stops"));
    c->callback([&run, a] {
        run = [a] {
            // (-o is a .png and the input is read as an EXR, but a link can make them one file)
            if (sameFile(a->output, a->input))
                failOption("--output",
                           a->output + " is the image being tonemapped; write the PNG elsewhere");
            const Image img = readExr(a->input, ExrValues::Preview);
            writePng(a->output, img, a->exposure);
            // (as make-medium and make-sky say what they wrote; it said nothing: helper 77)
            std::fprintf(stderr, "wrote %s: %dx%d, exposure %g stops\n", a->output.c_str(),
                         img.width, img.height, a->exposure);
            return 0;
        };
    });
}

}  // namespace shvol::app
