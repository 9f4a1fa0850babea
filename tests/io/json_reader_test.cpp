#include "shvol/io/json_reader.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "test_util.h"

#include <fstream>

#include "shvol/core/error.h"

namespace shvol {

namespace {
using shvol::test::messageOf;
}  // namespace

// canonicalJson: one text for equal values, another for different ones.
TEST(JsonReader, CanonicalJsonWritesIntegralNumbersAsIntegers) {
    EXPECT_EQ(canonicalJson(Json::parse(R"({"b": [1.0, -0.0, 2.5], "a": {"c": 1e3}})")),
              R"({"a":{"c":1000},"b":[1,0,2.5]})");
    EXPECT_EQ(canonicalJson(Json::parse("1e300")), "1e+300");  // no int64 holds it
    EXPECT_EQ(canonicalJson(Json::parse("18446744073709551615")), "18446744073709551615");
    EXPECT_NE(canonicalJson(Json::parse("[1]")), canonicalJson(Json::parse("[1.5]")));
    EXPECT_NE(canonicalJson(Json::parse(R"("1")")), canonicalJson(Json::parse("1")));
}

TEST(JsonReader, TypedAccessAndDefaults) {
    const Json j = Json::parse(R"({"a": 2.5, "n": 3, "s": "x", "v": [1, 2, 3], "b": true})");
    JsonReader r(j, "f.json", "");
    EXPECT_EQ(r.number("a"), 2.5);
    EXPECT_EQ(r.integer("n", 0, 0, 10), 3);
    EXPECT_EQ(r.string("s"), "x");
    EXPECT_EQ(r.vec3("v"), Vec3(1, 2, 3));
    EXPECT_TRUE(r.boolean("b", false));
    EXPECT_EQ(r.number("missing", 7.0), 7.0);
    EXPECT_NO_THROW(r.finish());
}

TEST(JsonReader, ErrorsNameFileAndPath) {
    const Json j =
        Json::parse(R"({"phase": {"g": "high", "typo": 1}, "n": 1.5, "v": [1, "a", 3]})");
    JsonReader r(j, "scene.json", "media[0]");
    EXPECT_EQ(messageOf([&] { r.object("phase").number("g"); }),
              "scene.json: media[0].phase.g: expected a number, got string \"high\"");
    EXPECT_EQ(messageOf([&] { r.integer("n", 0, 0, 10); }),
              "scene.json: media[0].n: expected an integer, got number 1.5");
    // An integral number written otherwise is that integer, range-checked as one.
    const Json k = Json::parse(R"({"a": 4.0, "b": 4e0, "c": -0.0, "d": 1e300, "e": 11.0})");
    JsonReader rk(k, "scene.json", "render");
    EXPECT_EQ(rk.integer("a", 0, 0, 10), 4);
    EXPECT_EQ(rk.integer("b", 0, 0, 10), 4);
    EXPECT_EQ(rk.integer("c", 1, 0, 10), 0);
    EXPECT_EQ(messageOf([&] { rk.integer("d", 0, 0, 10); }),
              "scene.json: render.d: value 1e+300 out of range [0, 10]");
    EXPECT_EQ(messageOf([&] { rk.integer("e", 0, 0, 10); }),
              "scene.json: render.e: value 11.0 out of range [0, 10]");
    EXPECT_EQ(messageOf([&] { r.vec3("v"); }),
              "scene.json: media[0].v[1]: expected a number, got string \"a\"");
    EXPECT_EQ(messageOf([&] { r.number("absent"); }),
              "scene.json: media[0].absent: missing required number");
    // A key that takes a number too says so (a scale's said "an array of 3 numbers"; helper
    // 161), also when missing.
    const Json scales = Json::parse(R"({"scale": {}, "axis": {}})");
    JsonReader rs(scales, "scene.json", "surfaces[0].transform");
    EXPECT_EQ(messageOf([&] { rs.vec3OrScalar("scale"); }),
              "scene.json: surfaces[0].transform.scale: expected a number or an array of 3 "
              "numbers, got object {}");
    EXPECT_EQ(messageOf([&] { rs.vec3("axis"); }),
              "scene.json: surfaces[0].transform.axis: expected an array of 3 numbers, got "
              "object {}");
    EXPECT_EQ(messageOf([&] { rs.vec3OrScalar("absent"); }),
              "scene.json: surfaces[0].transform.absent: missing required number or array of 3 "
              "numbers");
    EXPECT_EQ(messageOf([&] { rs.vec3("absent"); }),
              "scene.json: surfaces[0].transform.absent: missing required array of 3 numbers");
    // A null is named once, as "null" (it read "got null null"; helper 116).
    const Json nulls = Json::parse(R"({"fov": null, "on": null, "name": null})");
    JsonReader rn(nulls, "scene.json", "camera");
    EXPECT_EQ(messageOf([&] { rn.number("fov", 30.0); }),
              "scene.json: camera.fov: expected a number, got null");
    EXPECT_EQ(messageOf([&] { rn.boolean("on", false); }),
              "scene.json: camera.on: expected true or false, got null");
    EXPECT_EQ(messageOf([&] { rn.string("name", "x"); }),
              "scene.json: camera.name: expected a string, got null");
    EXPECT_EQ(messageOf([&] {
                  JsonReader p = r.object("phase");
                  p.number("g", 0.0, -1, 1);
              }),
              "scene.json: media[0].phase.g: expected a number, got string \"high\"");
    EXPECT_EQ(messageOf([&] {
                  JsonReader p(j["phase"], "scene.json", "media[0].phase");
                  p.raw("g");
                  p.finish();
              }),
              "scene.json: media[0].phase.typo: unknown key");
    // A key within 2 edits (and a third of its length) of one the object reads is named as the
    // likely typo: a swap, a letter lost, one too many (helper 77).
    for (const auto& [typo, meant] : std::vector<std::pair<std::string, std::string>>{
             {"desnity_scale", "density_scale"}, {"albdo", "albedo"}, {"albedoo", "albedo"}}) {
        const Json doc = {{typo, 1}};
        EXPECT_EQ(
            messageOf([&] {
                JsonReader m(doc, "scene.json", "media[0]");
                m.number("density_scale", 1.0);
                m.number("albedo", 1.0);
                m.finish();
            }),
            "scene.json: media[0]." + typo + ": unknown key (did you mean \"" + meant + "\"?)");
    }
    // ... and not a short key's nearest, nor one too far off.
    for (const std::string& key : {std::string("gg"), std::string("density")}) {
        const Json doc = {{key, 1}};
        EXPECT_EQ(messageOf([&] {
                      JsonReader m(doc, "scene.json", "media[0]");
                      m.number("g", 0.0);
                      m.number("density_scale", 1.0);
                      m.finish();
                  }),
                  "scene.json: media[0]." + key + ": unknown key");
    }
}

TEST(JsonReader, RangeAndChoice) {
    const Json j = Json::parse(R"({"g": 1.5, "t": "hgg"})");
    JsonReader r(j, "s.json", "p");
    EXPECT_EQ(messageOf([&] { r.number("g", 0, -1, 1); }),
              "s.json: p.g: value 1.5 out of range [-1, 1]");
    EXPECT_EQ(messageOf([&] {
                  r.choice("t", "hg", {"hg", "isotropic"});
              }),
              "s.json: p.t: unknown value \"hgg\"; expected one of \"hg\", \"isotropic\"");
}

TEST(JsonReader, RangeMessagesWriteNumbersAsAReaderWould) {
    const Json j = Json::parse(R"({"big": 2e12, "tiny": 1e-300, "seed": 9007199254740993.0,
                                   "third": 0.1, "neg": -2.5e-7})");
    JsonReader r(j, "s.json", "");
    // Powers of ten with a plain exponent, not 1000000000000 or 1e+12.
    EXPECT_EQ(messageOf([&] { r.number("big", 0, 1e-12, 1e12); }),
              "s.json: big: value 2e12 out of range [1e-12, 1e12]");
    EXPECT_EQ(messageOf([&] { r.number("tiny", 1, 1e-12, 1e12); }),
              "s.json: tiny: value 1e-300 out of range [1e-12, 1e12]");
    // Integers in full where that is the shortest exact text (2^53 + 1 reads as 2^53).
    EXPECT_EQ(messageOf([&] { r.number("seed", 0, 0, 1048576); }),
              "s.json: seed: value 9007199254740992 out of range [0, 1048576]");
    // The shortest decimal that reads back: 0.1, not 0.10000000000000001.
    EXPECT_EQ(messageOf([&] { r.number("third", 0, 0.25, 0.75); }),
              "s.json: third: value 0.1 out of range [0.25, 0.75]");
    // Small whole numbers as written (not 2e1, 1e2).
    EXPECT_EQ(messageOf([&] { r.number("big", 0, 20, 100); }),
              "s.json: big: value 2e12 out of range [20, 100]");
    EXPECT_EQ(messageOf([&] { r.number("neg", 0, 0, JsonReader::kUnbounded); }),
              "s.json: neg: value -2.5e-7 out of range (expected ≥ 0)");
}

TEST(JsonReader, MalformedFileNamesLineAndColumn) {
    const std::string path = testing::TempDir() + "/malformed.json";
    std::ofstream(path) << "{\n  \"a\": 1,\n  \"b\": ,\n}\n";
    const std::string m = messageOf([&] { parseJsonFile(path); });
    EXPECT_EQ(m.rfind(path + ": line 3, column 8: malformed JSON", 0), 0u) << m;
    EXPECT_EQ(messageOf([&] { parseJsonFile(path + ".missing"); }),
              path + ".missing: no such file");
    // (A directory would read as an empty document: "unexpected end of input".)
    EXPECT_EQ(messageOf([&] { parseJsonFile(testing::TempDir()); }),
              testing::TempDir() + ": not a regular file");
}

// A key given twice in one object is refused at the object's path (the parser would keep the last
// value silently), in nested objects and arrays too; and a NUL byte, after which the parser would
// read nothing more, at its line and column.
TEST(JsonReader, DuplicateKeysAndNulBytesAreRefused) {
    const std::string path = testing::TempDir() + "/dup.json";
    const auto refusal = [&](const std::string& text) {
        std::ofstream(path, std::ios::binary) << text;
        return messageOf([&] { parseJsonFile(path); });
    };
    EXPECT_EQ(refusal(R"({"a": 1, "a": 2})"),
              path + ": (top level): key \"a\" appears twice (the last would replace the first)");
    EXPECT_EQ(refusal(R"({"camera": {"fov": 30, "fov": 40}})"),
              path + ": camera: key \"fov\" appears twice (the last would replace the first)");
    EXPECT_EQ(refusal(R"({"x": [[1, {"k": 1}], {"k": 1, "j": {"k": 2}, "k": 3}]})"),
              path + ": x[1]: key \"k\" appears twice (the last would replace the first)");
    // A syntax error after a repeated key is the error named (the parser shows the key before
    // it checks the ':' that follows).
    EXPECT_EQ(
        refusal("{\"camera\": {\"fov\": 30,\n \"fov\" 40}}")
            .rfind(path + ": line 2, column 9: malformed JSON: syntax error while parsing object "
                          "separator",
                   0),
        0u)
        << refusal("{\"camera\": {\"fov\": 30,\n \"fov\" 40}}");
    EXPECT_EQ(refusal(std::string("{\"a\": 1}\n\0{\"b\"", 13)),
              path + ": line 2, column 1: malformed JSON: a NUL byte");
    // The same key in different objects, and equal values in an array, are fine.
    EXPECT_EQ(refusal(R"({"a": {"k": 1}, "b": {"k": 1}, "c": [{"k": 1}, {"k": 2}], "k": 0})"),
              "(no error)");
}

// A file name with an escaped NUL (\u0000, valid JSON) is refused: the system's calls would read
// the name up to it, and a scene naming "sky.exr\u0000x" rendered sky.exr with exit code 0 while
// its stats recorded a path that names no file (helper 54).
TEST(JsonReader, FileNamesWithANulCharacterAreRefused) {
    const std::string dir = testing::TempDir();
    std::ofstream(dir + "/sky.exr") << "x";
    const Json doc = Json::parse(R"({"file": "sky.exr\u0000x", "ok": "sky.exr"})");
    JsonReader r(doc, "scene.json", "environment");
    EXPECT_EQ(messageOf([&] { r.inputFile("file", dir); }),
              "scene.json: environment.file: the file name contains a NUL character (\\u0000)");
    EXPECT_EQ(r.inputFile("ok", dir), (std::filesystem::path(dir) / "sky.exr").lexically_normal());
}

TEST(JsonReader, Overrides) {
    Json j = Json::parse(R"({"render": {"spp": 4}, "media": [{"g": 0}]})");
    applyOverride(j, "render.spp=64", "s.json");
    applyOverride(j, "media.0.g=0.5", "s.json");
    applyOverride(j, "camera.type=orthographic", "s.json");
    applyOverride(j, "render.tag=[1,2]", "s.json");
    EXPECT_EQ(j["render"]["spp"], 64);
    EXPECT_EQ(j["media"][0]["g"], 0.5);
    EXPECT_EQ(j["camera"]["type"], "orthographic");
    EXPECT_EQ(j["render"]["tag"], Json::parse("[1,2]"));
    EXPECT_EQ(messageOf([&] { applyOverride(j, "media.3.g=1", "s.json"); }),
              "s.json: media: --set: index 3 out of range (1 element)");
    EXPECT_EQ(messageOf([&] { applyOverride(j, "render.spp.x=1", "s.json"); }),
              "s.json: render.spp: --set: cannot descend into a number");
    EXPECT_EQ(messageOf([&] { applyOverride(j, "media.-1.g=1", "s.json"); }),
              "s.json: media: --set: \"-1\" is not an index of the array (1 element)");
    EXPECT_EQ(messageOf([&] { applyOverride(j, "media.x=1", "s.json"); }),
              "s.json: media: --set: \"x\" is not an index of the array (1 element)");
    // A document that is no object is refused as such, as it is without overrides (a scene of
    // `null` would otherwise become one of defaults).
    Json list = Json::array(), null;
    EXPECT_EQ(messageOf([&] { applyOverride(list, "render.spp=1", "s.json"); }),
              "s.json: (top level): expected an object, got array");
    EXPECT_EQ(messageOf([&] { applyOverride(null, "render.spp=1", "s.json"); }),
              "s.json: (top level): expected an object, got null");
    // (named at the key's place in the scene, not at the value's "(top level)")
    EXPECT_EQ(
        messageOf([&] { applyOverride(j, "camera={\"fov\": 30, \"fov\": 40}", "s.json"); }),
        "s.json: --set camera={\"fov\": 30, \"fov\": 40}: camera: key \"fov\" appears twice (the "
        "last would replace the first)");
    EXPECT_EQ(messageOf([&] {
                  applyOverride(j, "media.0.phase={\"a\": [{\"g\": 1, \"g\": 2}]}", "s.json");
              }),
              "s.json: --set media.0.phase={\"a\": [{\"g\": 1, \"g\": 2}]}: media[0].phase.a[0]: "
              "key \"g\" appears twice (the last would replace the first)");
    EXPECT_EQ(messageOf([&] { applyOverride(j, "nonsense", "s.json"); }),
              "s.json: --set nonsense: expected key.path=value");
    // An index into an array the scene does not have (it made an object {"0": …}, refused by
    // the loader as "surfaces: expected an array of objects"; helper 77).
    EXPECT_EQ(messageOf([&] { applyOverride(j, "surfaces[0].bsdf.type=lambert", "s.json"); }),
              "s.json: surfaces: --set: index 0 of an array the scene does not have: give the "
              "whole array (--set 'surfaces=[…]')");
    EXPECT_EQ(messageOf([&] { applyOverride(j, "camera.position.0=1", "s.json"); }),
              "s.json: camera.position: --set: index 0 of an array the scene does not have: give "
              "the whole array (--set 'camera.position=[…]')");
    EXPECT_FALSE(j["camera"].contains("position"));
    // ... unless the key is a typo of one its object has, or of a scene array (helper 81)
    EXPECT_EQ(messageOf([&] { applyOverride(j, "medai[0].albedo=0.5", "s.json"); }),
              "s.json: medai: --set: unknown key (did you mean \"media\"?)");
    EXPECT_EQ(messageOf([&] { applyOverride(j, "surfacs[0].bsdf.type=lambert", "s.json"); }),
              "s.json: surfacs: --set: unknown key (did you mean \"surfaces\"?)");
    EXPECT_EQ(messageOf([&] { applyOverride(j, "camera.tpye.0=1", "s.json"); }),
              "s.json: camera.tpye: --set: unknown key (did you mean \"type\"?)");
    EXPECT_FALSE(applyOverride(j, "surfaces[0].bsdf=null", "s.json"));  // deletes nothing
}

// --set as a user expects it: the error messages' bracket notation, null deletes, a new type
// drops the old type's keys, and a file given on the command line is relative to the current
// directory.
TEST(JsonReader, OverrideSemantics) {
    Json j = Json::parse(
        R"({"media": [{"albedo": 1, "phase": {"type": "hg", "g": 0.5, "sampling": "sh"}}]})");
    applyOverride(j, "media[0].albedo=0.7", "s.json");
    EXPECT_EQ(j["media"][0]["albedo"], 0.7);
    applyOverride(j, "media[0].albedo=null", "s.json");
    EXPECT_FALSE(j["media"][0].contains("albedo"));
    applyOverride(j, "media.0.phase.type=hg", "s.json");  // same type: keys stay
    EXPECT_EQ(j["media"][0]["phase"]["g"], 0.5);
    applyOverride(j, "media.0.phase.type=tabulated", "s.json");  // (SH sampling is every type's)
    EXPECT_EQ(j["media"][0]["phase"], Json::parse(R"({"type": "tabulated", "sampling": "sh"})"));
    applyOverride(j, "media.0.phase.file=tables/mie.csv", "s.json");
    const std::string expected =
        (std::filesystem::current_path() / "tables/mie.csv").lexically_normal().string();
    EXPECT_EQ(j["media"][0]["phase"]["file"], expected);
    applyOverride(j, "media.0.phase.file=/abs/mie.csv", "s.json");
    EXPECT_EQ(j["media"][0]["phase"]["file"], "/abs/mie.csv");
    // A camera, medium or surface keeps the keys every type of it reads (they went too, without
    // a word: a camera's resolution, a medium's albedo, a surface's name; helper 73).
    Json scene = Json::parse(R"({
        "camera": {"type": "perspective", "position": [0, -6, 0], "fov": 20, "resolution": [8, 8]},
        "media": [{"type": "homogeneous", "sigma_t": 3, "albedo": 0.2, "phase": {"type": "hg"},
                   "boundary": "glass"}],
        "surfaces": [{"type": "sphere", "radius": 2, "name": "glass", "bsdf": {"type": "null"},
                      "emission": 2, "emission_two_sided": true, "transform": {"scale": 2}}]})");
    applyOverride(scene, "camera.type=orthographic", "s.json");
    EXPECT_EQ(scene["camera"], Json::parse(R"({"type": "orthographic", "position": [0, -6, 0],
                                              "resolution": [8, 8]})"));
    applyOverride(scene, "media.0.type=vdb", "s.json");
    EXPECT_EQ(scene["media"][0], Json::parse(R"({"type": "vdb", "albedo": 0.2,
                                                "phase": {"type": "hg"}, "boundary": "glass"})"));
    applyOverride(scene, "surfaces[0].type=mesh", "s.json");
    EXPECT_EQ(scene["surfaces"][0],
              Json::parse(R"({"type": "mesh", "name": "glass", "bsdf": {"type": "null"},
                              "emission": 2, "emission_two_sided": true,
                              "transform": {"scale": 2}})"));
    // An object that names no type has its default one (the loader's): another type starts it
    // afresh as well, and the same one keeps its keys (helper 181: a BSDF of reflectance 0.3
    // set to a mirror kept 0.3, and an image sky set on a constant's radiance blamed the
    // radiance). The defaults agree with the loader's:
    // SceneLoader.TypelessObjectsHaveTheTypeOverridesAssume.
    Json typeless = Json::parse(R"({"camera": {"fov": 20, "resolution": [8, 8]},
        "environment": {"radiance": 2, "lower_hemisphere_black": true},
        "media": [{"density_scale": 3, "albedo": 0.5,
                   "phase": {"g": 0.5, "sampling": "sh", "order": 8},
                   "shape": {"min": [0, 0, 0]}}],
        "surfaces": [{"file": "a.obj", "name": "s", "bsdf": {"reflectance": 0.3}}]})");
    const Json typelessBefore = typeless;
    const std::pair<const char*, const char*> sameTypes[] = {
        {"camera.type=perspective", "/camera"},
        {"environment.type=constant", "/environment"},
        {"media.0.type=vdb", "/media/0"},
        {"media.0.phase.type=isotropic", "/media/0/phase"},
        {"media.0.shape.type=box", "/media/0/shape"},
        {"surfaces.0.type=mesh", "/surfaces/0"},
        {"surfaces.0.bsdf.type=lambert", "/surfaces/0/bsdf"}};
    for (const auto& [same, at] : sameTypes) {
        Json t = typelessBefore;
        applyOverride(t, same, "s.json");
        const Json::json_pointer ptr(at);
        Json expected = typelessBefore[ptr];
        expected["type"] = std::string(same).substr(std::string(same).find('=') + 1);
        EXPECT_EQ(t[ptr], expected) << same;
    }
    applyOverride(typeless, "camera.type=orthographic", "s.json");
    EXPECT_EQ(typeless["camera"], Json::parse(R"({"type": "orthographic", "resolution": [8, 8]})"));
    applyOverride(typeless, "environment.type=image", "s.json");
    // (what every type of a sky or phase function reads stays: helper 183)
    EXPECT_EQ(typeless["environment"],
              Json::parse(R"({"type": "image", "lower_hemisphere_black": true})"));
    applyOverride(typeless, "media.0.phase.type=hg", "s.json");
    EXPECT_EQ(typeless["media"][0]["phase"],
              Json::parse(R"({"type": "hg", "sampling": "sh", "order": 8})"));
    applyOverride(typeless, "media.0.shape.type=sphere", "s.json");
    EXPECT_EQ(typeless["media"][0]["shape"], Json::parse(R"({"type": "sphere"})"));
    applyOverride(typeless, "media.0.type=homogeneous", "s.json");
    EXPECT_EQ(typeless["media"][0], Json::parse(R"({"type": "homogeneous", "albedo": 0.5,
        "phase": {"type": "hg", "sampling": "sh", "order": 8}})"));
    applyOverride(typeless, "surfaces.0.bsdf.type=mirror", "s.json");
    EXPECT_EQ(typeless["surfaces"][0]["bsdf"], Json::parse(R"({"type": "mirror"})"));
    applyOverride(typeless, "surfaces.0.type=sphere", "s.json");
    EXPECT_EQ(typeless["surfaces"][0], Json::parse(R"({"type": "sphere", "name": "s",
                                                      "bsdf": {"type": "mirror"}})"));
    // type=null is the null BSDF's type, not a deletion (which left the default BSDF).
    Json surface =
        Json::parse(R"({"surfaces": [{"bsdf": {"type": "lambert", "reflectance": 1}}]})");
    applyOverride(surface, "surfaces.0.bsdf.type=null", "s.json");
    EXPECT_EQ(surface["surfaces"][0]["bsdf"], Json::parse(R"({"type": "null"})"));
    EXPECT_TRUE(applyOverride(surface, "surfaces.0.bsdf=null", "s.json"));
    EXPECT_FALSE(surface["surfaces"][0].contains("bsdf"));
    // ... also where the surface has no bsdf yet.
    EXPECT_TRUE(applyOverride(surface, "surfaces.0.bsdf.type=null", "s.json"));
    EXPECT_EQ(surface["surfaces"][0]["bsdf"], Json::parse(R"({"type": "null"})"));
    // A deletion that finds nothing says so and leaves the document as it was, under a missing
    // key too (the walk made it null, which the loader refused).
    const Json before = surface;
    EXPECT_FALSE(applyOverride(surface, "surfaces.0.nosuch=null", "s.json"));
    EXPECT_FALSE(applyOverride(surface, "surfaces.0.nosuch.deeper=null", "s.json"));
    EXPECT_EQ(surface, before);
    // Other types are deleted, so that their default applies again (there is no null camera).
    Json camera = Json::parse(R"({"camera": {"type": "orthographic"}})");
    applyOverride(camera, "camera.type=null", "s.json");
    EXPECT_FALSE(camera["camera"].contains("type"));
    EXPECT_EQ(messageOf([&] { applyOverride(j, "media.0=null", "s.json"); }),
              "s.json: media: --set: array elements cannot be deleted");
    EXPECT_EQ(messageOf([&] { applyOverride(j, "media.=1", "s.json"); }),
              "s.json: --set media.=1: empty component in key path");
}

// What an override sets: its key and the keys inside it, and what an object or array value holds.
TEST(JsonReader, OverrideSetsTheKeysItsValueHolds) {
    EXPECT_TRUE(overrideSets("render.spp", 4, {"render", "spp"}));
    EXPECT_FALSE(overrideSets("render.spp.x", 4, {"render", "spp"}));  // (an error elsewhere)
    EXPECT_TRUE(overrideSets("render", Json::parse(R"({"spp": 3})"), {"render", "spp"}));
    EXPECT_FALSE(overrideSets("render", Json::parse(R"({"seed": 3})"), {"render", "spp"}));
    EXPECT_FALSE(overrideSets("render.seed", 3, {"render", "spp"}));
    EXPECT_TRUE(overrideSets("media.2.lookup", "openvdb", {"media", "*", "lookup"}));
    EXPECT_TRUE(
        overrideSets("media.0", Json::parse(R"({"lookup": "openvdb"})"), {"media", "*", "lookup"}));
    EXPECT_TRUE(
        overrideSets("media", Json::parse(R"([{}, {"lookup": 1}])"), {"media", "*", "lookup"}));
    EXPECT_FALSE(overrideSets("media", Json::parse("[]"), {"media", "*", "lookup"}));
    EXPECT_FALSE(overrideSets("media.0.albedo", 0.5, {"media", "*", "lookup"}));
}

// A malformed key path is refused at once (brackets used to be dropped wherever they were, so
// camera[fov=0.5 set camera.fov, and camera]fov was named as the unknown key "camerafov"), and
// so is a number beyond a double, which used to become the string "1e400".
TEST(JsonReader, OverrideRefusesMalformedKeyPathsAndNumbers) {
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"camera[fov=0.5", "expected an index in brackets, as in media[0]"},
        {"media[0]].albedo=0.5", "']' without '[' in key path"},
        {"media[0][albedo]=0.5", "expected an index in brackets, as in media[0]"},
        {"media[]=1", "expected an index in brackets, as in media[0]"},
        {"camera]fov=1", "']' without '[' in key path"},
        {"media[0]albedo=1", "expected '.' or '[' after ']' in key path"},
        {"[0].x=1", "a key path starts with a name"},
        {".x=1", "empty component in key path"},
        {"a..b=1", "empty component in key path"},
        {"media[0].=1", "empty component in key path"},
    };
    for (const auto& c : cases) {
        Json j = Json::parse(R"({"camera": {"fov": 40}, "media": [{"albedo": 1}]})");
        const Json before = j;
        EXPECT_EQ(messageOf([&] { applyOverride(j, c.first, "s.json"); }),
                  "s.json: --set " + c.first + ": " + c.second);
        EXPECT_EQ(j, before) << c.first;
    }
    // A control character (no scene key has one), written escaped in the message.
    Json j = Json::parse(R"({"media": [{"albedo": 1, "phase": {"g": 0}}]})");
    EXPECT_EQ(messageOf([&] { applyOverride(j, std::string("media\0.albedo=1", 15), "s.json"); }),
              "s.json: --set media\\u0000.albedo=1: a control character in key path");
    EXPECT_EQ(messageOf([&] { applyOverride(j, "camera.\tfov=1", "s.json"); }),
              "s.json: --set camera.\\u0009fov=1: a control character in key path");
    applyOverride(j, "media[0].phase.g=0.5", "s.json");  // both notations, and nested indices
    applyOverride(j, "media.0.albedo=0.25", "s.json");
    EXPECT_EQ(j["media"][0]["phase"]["g"], 0.5);
    EXPECT_EQ(j["media"][0]["albedo"], 0.25);
    applyOverride(j, "m=[[1,2],[3,4]]", "s.json");
    applyOverride(j, "m[1][0]=7", "s.json");
    EXPECT_EQ(j["m"], Json::parse("[[1,2],[7,4]]"));
    EXPECT_EQ(
        messageOf([&] { applyOverride(j, "media[0].albedo=1e400", "s.json"); }),
        "s.json: --set media[0].albedo=1e400: number beyond the range of a double (±1.8e308)");
    EXPECT_EQ(messageOf([&] { applyOverride(j, "render.spp=" + std::string(400, '9'), "s.json"); }),
              "s.json: --set render.spp=" + std::string(77, '9') +
                  "...: number beyond the range of a double (±1.8e308)");
}

// Found by fuzz/scene_fuzzer and fuzz/phase_spec_fuzzer: a --set value that is not JSON is kept
// as a string, bytes and all; quoting it in a message must not throw nlohmann's type_error 316
// (invalid UTF-8), which escaped as a non-shvol exception.
TEST(JsonReader, InvalidUtf8InAValueGivesOneLine) {
    Json j = Json::object();
    applyOverride(j, "render.spp=\xb4\xff", "s.json");
    JsonReader render(j["render"], "s.json", "render");
    EXPECT_EQ(messageOf([&] { render.integer("spp", 1, 1, 10); }),
              "s.json: render.spp: expected an integer, got string \"\xEF\xBF\xBD\xEF\xBF\xBD\"");
    const Json k = {{"g", std::string("c-0.or\xca")}};
    EXPECT_EQ(messageOf([&] { JsonReader(k, "spec", "").number("g"); }),
              "spec: g: expected a number, got string \"c-0.or\xEF\xBF\xBD\"");
}

// A value nested 100000 levels deep (a 200 KB --set value or scene) is quoted in a message
// without recursing through it (Json::dump did, and overflowed the stack).
TEST(JsonReader, DeeplyNestedValueInAMessage) {
    Json j = Json::object();
    const auto nested = [](size_t n) { return std::string(n, '[') + std::string(n, ']'); };
    applyOverride(j, "render.spp=" + nested(kMaxJsonDepth), "s.json");
    JsonReader render(j["render"], "s.json", "render");
    EXPECT_EQ(messageOf([&] { render.integer("spp", 1, 1, 10); }),
              "s.json: render.spp: expected an integer, got array " + std::string(37, '[') + "...");
    // Deeper is refused as it is parsed (100 000 levels were taken, and a scene file's crashed
    // the recursive copies after it: helper 96).
    EXPECT_EQ(messageOf([&] { applyOverride(j, "render.spp=" + nested(100000), "s.json"); }),
              "s.json: --set render.spp=" + std::string(77, '[') +
                  "...: render.spp[0][0][0][0]…: objects and arrays nested more than 256 levels "
                  "deep");
}

// A file nested deeper than kMaxJsonDepth is refused at the level that passes it, however deep
// (a scene of 100 000 nested arrays under "media", 200 kB, crashed the loader's copies); at the
// limit it parses.
TEST(JsonReader, NestingDeeperThanTheLimitIsRefused) {
    const std::string path = testing::TempDir() + "/deep.json";
    const auto refusal = [&](size_t arrays) {
        std::ofstream(path) << "{\"media\": " + std::string(arrays, '[') +
                                   std::string(arrays, ']') + "}";
        return messageOf([&] { parseJsonFile(path); });
    };
    EXPECT_EQ(refusal(kMaxJsonDepth - 1), "(no error)");  // with the top-level object: the limit
    const std::string deep =
        path + ": media[0][0][0]…: objects and arrays nested more than 256 levels deep";
    EXPECT_EQ(refusal(kMaxJsonDepth), deep);
    EXPECT_EQ(refusal(100000), deep);
    std::string objects = "1";  // objects in objects, named by their keys
    for (int k = 0; k < 300; ++k) objects = R"({"a": )" + objects + "}";
    std::ofstream(path) << objects;
    EXPECT_EQ(messageOf([&] { parseJsonFile(path); }),
              path + ": a.a.a.a…: objects and arrays nested more than 256 levels deep");
}

// A file shvol wrote, read where it is only consulted (a render's stats): its JSON, or discarded
// when malformed or nested deeper than the limit (the batch copied a stats file's value, and a
// deep one would overflow the stack as a scene did).
TEST(JsonReader, OwnFilesTooDeepOrMalformedAreDiscarded) {
    const std::string path = testing::TempDir() + "/own.stats.json";
    std::ofstream(path) << R"({"spp": 4, "x": [[1]]})";
    EXPECT_EQ(parseOwnJsonFile(path), Json::parse(R"({"spp": 4, "x": [[1]]})"));
    std::ofstream(path) << R"({"spp": )";
    EXPECT_TRUE(parseOwnJsonFile(path).is_discarded());
    std::ofstream(path) << "{\"x\": " + std::string(100000, '[') + std::string(100000, ']') + "}";
    EXPECT_TRUE(parseOwnJsonFile(path).is_discarded());
    EXPECT_TRUE(parseOwnJsonFile(path + ".missing").is_discarded());
    // The same limit as a scene's: 255 arrays in the object pass, 256 do not.
    for (const size_t arrays : {kMaxJsonDepth - 1, kMaxJsonDepth}) {
        std::ofstream(path) << "{\"x\": " + std::string(arrays, '[') + std::string(arrays, ']') +
                                   "}";
        EXPECT_EQ(parseOwnJsonFile(path).is_discarded(), arrays == kMaxJsonDepth) << arrays;
    }
}

}  // namespace shvol
