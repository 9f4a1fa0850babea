#include "shvol/io/scene_loader.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>

#include "shvol/core/error.h"
#include "shvol/io/exr.h"
#include "shvol/io/mesh_file.h"
#include "shvol/io/vdb.h"
#include "shvol/lights/product_sampler.h"
#include "shvol/media/homogeneous_medium.h"

namespace shvol {

namespace fs = std::filesystem;

namespace {

/// The directory relative file names in the scene are resolved against.
std::string sceneDir(const JsonReader& r) {
    return fs::path(r.file()).parent_path().string();
}

/// key, or its element i (key[i]) when r[key] is an array: where an error in component i is.
std::string componentKey(JsonReader& r, const std::string& key, int i) {
    return r.has(key) && r.raw(key).is_array() ? key + "[" + std::to_string(i) + "]" : key;
}

/// r[key] as a number or three, each in [lo, hi]: "albedo: value 2 out of range" for a number,
/// "albedo[0]: value 2 out of range" for an element of [x, y, z] (it said "component 2", which
/// read as the index; helper 84).
Vec3 vec3OrScalarIn(JsonReader& r, const std::string& key, const Vec3& def, double lo, double hi) {
    const Vec3 v = r.vec3OrScalar(key, def);
    for (int i = 0; i < 3; ++i)
        if (!(v[i] >= lo && v[i] <= hi))
            r.rangeError(componentKey(r, key, i), "value", v[i], lo, hi);
    return v;
}

Spectrum spectrum(JsonReader& r, const std::string& key, double def, double lo, double hi) {
    return vec3OrScalarIn(r, key, Vec3::Constant(def), lo, hi).array();
}

/// A point of the scene, within the ray tracer's range (±kMaxSurfaceCoordinate, as surfaces and
/// translations are): beyond about 10¹⁶ a medium in front of a camera there vanished without a
/// word (helper 73: an absorber's image mean 1.0 for e⁻²).
Vec3 pointInRange(JsonReader& r, const std::string& key, const Vec3& def) {
    const Vec3 p = r.vec3(key, def);
    for (int i = 0; i < 3; ++i)
        if (!(std::abs(p[i]) <= kMaxSurfaceCoordinate))
            r.rangeError(componentKey(r, key, i), "value", p[i], -kMaxSurfaceCoordinate,
                         kMaxSurfaceCoordinate);
    return p;
}

Camera readCamera(JsonReader r) {
    Camera c;
    const std::string type = r.choice("type", "perspective", {"perspective", "orthographic"});
    c.type = type == "perspective" ? Camera::Type::Perspective : Camera::Type::Orthographic;
    c.position = pointInRange(r, "position", c.position);
    c.target = pointInRange(r, "target", c.target);
    c.up = r.vec3("up", c.up);
    const Vec3 view = c.target - c.position;
    if (!view.allFinite())
        r.error("target", "is too far from the camera position (their distance overflows)");
    // (Either key may be the one given wrong: a position moved onto the target blamed the
    // target alone; helper 122.)
    if (view.isZero(0)) r.error("target", "equals camera.position: the camera looks nowhere");
    if (c.up.isZero(0)) r.error("up", "is the zero vector");
    if (view.stableNormalized().cross(c.up.stableNormalized()).norm() < 1e-9)
        r.error("up", "is parallel to the viewing direction");
    c.fovDegrees = r.number("fov", c.fovDegrees, 1e-3, 179);
    c.extent = r.number("extent", c.extent, 1e-9, 1e9);
    if (r.has("resolution")) {
        const Json& res = r.raw("resolution");
        // (An integral number however written, 4.0 or 4e0, as every integer key takes it: the
        // type of the JSON number was asked; helper 74.)
        const auto side = [&](size_t i) {
            const double v = res.is_array() && res.size() == 2 && res[i].is_number()
                                 ? res[i].get<double>()
                                 : 0.0;
            return v >= 1 && v <= 16384 && v == std::floor(v) ? int(v) : 0;
        };
        if (side(0) == 0 || side(1) == 0)
            r.error("resolution", "expected [width, height], integers in [1, 16384]");
        c.width = side(0);
        c.height = side(1);
    } else {
        r.note("resolution", {c.width, c.height});
    }
    r.finish();
    return c;
}

RenderSettings readSettings(JsonReader r) {
    RenderSettings s;
    s.spp = r.integer("spp", s.spp, 1, kMaxSpp);
    s.seed = uint64_t(r.wholeNumber("seed", 1, 0, 9007199254740992.0));
    s.maxDepth = r.integer("max_depth", s.maxDepth, 0, 1 << 20);
    s.rrDepth = r.integer("rr_depth", s.rrDepth, 0, 1 << 20);
    s.rrThreshold = r.numberOrAuto("rr_threshold", 1e-6, 1);  // "auto", the default: unset
    s.nee = r.booleanOrAuto("nee");
    s.sampler =
        r.choice("sampler", sampleStreamName(s.sampler), {"sobol", "independent"}) == "sobol"
            ? SampleStream::Sobol
            : SampleStream::Independent;
    s.transmittance = r.choice("transmittance", "ratio", {"ratio", "delta"}) == "ratio"
                          ? TransmittanceEstimator::Ratio
                          : TransmittanceEstimator::Delta;
    const std::string ls = r.choice("light_sampling", lightSamplingName(s.lightSampling),
                                    {"environment", "wavelet", "product"});
    s.lightSampling = ls == "wavelet"   ? LightSampling::Wavelet
                      : ls == "product" ? LightSampling::Product
                                        : LightSampling::Environment;
    const std::string mis = r.choice("mis", misHeuristicName(s.mis), {"balance", "power", "none"});
    s.mis = mis == "power"  ? MisHeuristic::Power
            : mis == "none" ? MisHeuristic::None
                            : MisHeuristic::Balance;
    s.productOrder = r.integer("product_order", s.productOrder, 1, ProductSampler::kMaxOrder);
    // "auto", the default: ⌈log₂ order⌉ + 2 in [3, 9], chosen by the sampler (−1).
    s.productDepth = r.integerOrAuto("product_depth", 0, 12).value_or(-1);
    JsonReader rc = r.objectOrEmpty("radiance_cache");
    RadianceCacheSettings& c = s.radianceCache;
    c.enabled = rc.boolean("enabled", c.enabled);
    // a ≤ 1: beyond, records facing away from a query (√(1 − N·N_i) up to √2) would count.
    c.accuracy = rc.number("accuracy", c.accuracy, 1e-3, 1);
    c.hshOrder = rc.integer("hsh_order", c.hshOrder, 1, 20);
    c.raysPerRecord = rc.integer("rays_per_record", c.raysPerRecord, 1, 1 << 20);
    c.maxRecords = rc.integer("max_records", c.maxRecords, 0, 1 << 24);
    c.lightSamples = rc.integer("light_samples", c.lightSamples, 1, 1024);
    rc.finish();
    r.finish();
    return s;
}

/// Keys that belong to another type of the object: each present one is an error saying which type
/// takes it (clearer than "unknown key" for a documented key).
void refuseKeysOfType(const JsonReader& r, const char* type,
                      std::initializer_list<const char*> keys) {
    for (const char* k : keys)
        if (r.has(k)) r.error(k, std::string("only with \"type\": \"") + type + "\"");
}

constexpr std::initializer_list<const char*> kVdbKeys = {
    "file",          "grid",   "density_scale", "transform",       "majorant_grid",
    "majorant_cell", "lookup", "decomposition", "regular_tracking"};

/// What the loader reads: everything, or (Check) every key of the document but not the contents
/// of the grids, skies and meshes it names, which must exist (checkScene).
enum class Contents { Load, Check };

Environment readEnvironment(JsonReader r, RenderSettings& settings, Contents contents) {
    const std::string type = r.choice("type", "constant", {"constant", "image"});
    const bool lowerBlack = r.boolean("lower_hemisphere_black", false);
    // Top-K compression of the sky wavelet used by the wavelet and product light samplers.
    settings.waveletCoefficients =
        size_t(r.wholeNumber("wavelet_coefficients", 0, 0, 9007199254740992.0));
    if (type == "constant") {
        const Spectrum L = spectrum(r, "radiance", 1, 0, JsonReader::kUnbounded);
        refuseKeysOfType(r, "image", {"file", "scale", "rotation", "mapping"});
        r.finish();
        return Environment::constant(L, lowerBlack);
    }
    const std::string file = r.inputFile("file", sceneDir(r));
    const double scale = r.number("scale", 1, 0, JsonReader::kUnbounded);
    const double rotation = r.number("rotation", 0, -1e6, 1e6);
    const LatLongMapping mapping =
        latLongMappingFromName(r.choice("mapping", "blender", {"blender", "shvol"}));
    refuseKeysOfType(r, "constant", {"radiance"});
    r.finish();
    if (contents == Contents::Check) return Environment::constant(Spectrum::Zero(), lowerBlack);
    // (named with the scene and the key too, as a mesh is: helper 181)
    Environment sky = Environment::image(r.readInput("file", [&] { return readExr(file); }), scale,
                                         rotation, lowerBlack, mapping);
    // A sky whose own radiance no image can hold: every pixel that sees its brightest texel
    // would be written as inf (after the whole render, with a warning; helper 116). Only the
    // texels seen count (not those below a black lower hemisphere; helper 120).
    if (const double peak = sky.brightestSeen();
        peak * scale > double(std::numeric_limits<float>::max())) {
        char text[200];
        std::snprintf(text, sizeof text,
                      "%.9g times the largest value the image shows, %.9g, is %.9g, beyond the "
                      "float32 range (3.4028235e38) of the images a render writes",
                      scale, peak, peak * scale);
        r.error("scale", text);
    }
    return sky;
}

Eigen::Affine3d readTransform(JsonReader r) {
    // Bounded, so that the transform stays invertible with any grid's voxel size (a scale of
    // 1e-300 would pass a positivity check and make the medium's transform singular at load; a
    // translation of 1e308 overflowed the inverse, and the error blamed the .vdb; ±1e15 is the ray
    // tracer's range).
    const Vec3 t = pointInRange(r, "translate", Vec3::Zero());
    const Vec3 s = vec3OrScalarIn(r, "scale", Vec3::Ones(), 1e-12, 1e12);
    Eigen::Affine3d m = Eigen::Affine3d::Identity();
    m.translate(t);
    if (r.has("rotate")) {
        JsonReader rot = r.object("rotate");
        const Vec3 axis = rot.vec3("axis", Vec3(0, 0, 1));
        // (scaled by its largest component first: the norm of [0, 0, 1e200] overflowed and that
        // of [0, 0, 1e-300] underflowed, which shrank the object to nothing or refused the axis)
        if (axis.cwiseAbs().maxCoeff() == 0) rot.error("axis", "must not be zero");
        // (Bounded: 1e308° overflowed to a rotation of NaN, blamed on the grid; helper 73.)
        const double deg = rot.number("degrees", 0.0, -1e6, 1e6);
        rot.finish();
        m.rotate(Eigen::AngleAxisd(deg * Pi / 180, axis.stableNormalized()));
    }
    m.scale(s);
    r.finish();
    return m;
}

Bsdf readBsdf(JsonReader r) {
    const std::string type =
        r.choice("type", "lambert", {"lambert", "phong", "ward", "mirror", "dielectric", "null"});
    Bsdf b = Bsdf::null();
    if (type == "lambert") {
        b = Bsdf::lambert(spectrum(r, "reflectance", 0.5, 0, 1));
    } else if (type == "phong" || type == "ward") {
        const Spectrum rd = spectrum(r, "diffuse", 0, 0, 1);
        const Spectrum rs = spectrum(r, "specular", 0.5, 0, 1);
        // ρ_d + ρ_s ≤ 1 keeps the lobes energy-conserving (surfaces/bsdf.h).
        if (((rd + rs) > 1 + 1e-12).any()) {
            Eigen::Index c = 0;
            (rd + rs).maxCoeff(&c);
            char sum[64];  // (with the numbers behind it: helper 77)
            std::snprintf(sum, sizeof sum, "%.6g + %.6g", rd[c], rs[c]);
            const bool grey = (rd == rd[0]).all() && (rs == rs[0]).all();
            r.error("specular", "diffuse + specular exceeds 1 (" + std::string(sum) +
                                    (grey ? "" : std::string(" in channel ") + "rgb"[c]) + ")");
        }
        if (type == "phong") {
            b = Bsdf::phong(rd, rs, r.number("exponent", 22, 0, 1e6));
        } else {
            // One roughness or two: with both, which one wins would be a guess.
            if (r.has("alpha") && (r.has("alpha_x") || r.has("alpha_y")))
                r.error("alpha", "give alpha (isotropic) or alpha_x and alpha_y, not both");
            // Only the keys of the form given are read (and resolved): the resolved scene of an
            // isotropic lobe with alpha_x and alpha_y filled in too was refused on reload.
            if (r.has("alpha_x") || r.has("alpha_y")) {
                b = Bsdf::ward(rd, rs, r.number("alpha_x", 0.1, 1e-4, 10),
                               r.number("alpha_y", 0.1, 1e-4, 10));
            } else {
                const double a = r.number("alpha", 0.1, 1e-4, 10);
                b = Bsdf::ward(rd, rs, a, a);
            }
        }
    } else if (type == "mirror") {
        b = Bsdf::mirror(spectrum(r, "reflectance", 1, 0, 1));
    } else if (type == "dielectric") {
        b = Bsdf::dielectric(r.number("ior", 1.5, 1e-3, 100));
    }
    r.finish();
    return b;
}

/// Why a closed mesh cannot be turned to face outwards (Surface::faceOutwards).
std::string mixedShellsOfAnEmitter(const Surface& s) {
    return s.name +
           ": some of its shells face inwards and others outwards, and it emits from one side, "
           "which cannot be turned shell by shell; wind its shells alike (outwards, a hollow's "
           "inner wall inwards) or make its emission two-sided";
}

/// surfaces[index]; under Contents::Check a mesh's file is not read (its mesh stays empty).
Surface readSurface(JsonReader r, size_t index, Contents contents) {
    const std::string type = r.choice("type", "mesh", {"mesh", "rectangle", "disk", "sphere"});
    const Eigen::Affine3d toWorld =
        r.has("transform") ? readTransform(r.object("transform")) : Eigen::Affine3d::Identity();
    Surface s;
    if (type == "mesh") {
        const std::string file = r.inputFile("file", sceneDir(r));
        s.kind = Surface::Kind::Mesh;
        if (contents == Contents::Load) {
            // (named with the scene and the surface too: the mesh file's own place alone did
            // not say which surface of which scene; helper 143)
            s.mesh = r.readInput("file", [&] { return readMesh(file, &toWorld, &s.places); });
            widestAngleFirst(s.mesh);
        }
    } else if (type == "rectangle") {
        s = Surface::rectangle(toWorld);
    } else if (type == "disk") {
        const Eigen::Matrix3d l = toWorld.linear();
        if (std::abs((l * Vec3::UnitX()).norm() - (l * Vec3::UnitY()).norm()) >
            1e-9 * (l * Vec3::UnitX()).norm())
            r.error("transform", "a disk needs the same scale along x and y");
        s = Surface::disk(toWorld);
    } else {
        const double radius = r.number("radius", 1, 1e-12, 1e12);
        const Vec3 scale = toWorld.linear().colwise().norm();
        if (scale.maxCoeff() - scale.minCoeff() > 1e-9 * scale.maxCoeff())
            r.error("transform", "a sphere needs a uniform scale");
        s = Surface::sphere(toWorld * r.vec3("center", Vec3::Zero()), radius * scale[0]);
    }
    s.orient(toWorld);  // (meshes and spheres; rectangles and disks are made oriented)
    // (A mesh that Check mode did not read has no vertices: reach 0.)
    if (const double reach = s.reach(); !(reach <= kMaxSurfaceCoordinate)) {
        if (type != "mesh") r.error("", surfaceReachMessage(reach));
        // A mesh's first vertex beyond the bound (there is one: its reach is its vertices'), at
        // its place in the file (the key alone named neither; helper 161).
        const auto beyond = [](const Vec3& p) { return !(reachOf(p) <= kMaxSurfaceCoordinate); };
        const auto far = std::find_if(s.mesh.p.begin(), s.mesh.p.end(), beyond);
        r.error("file", s.places.file + ": " + s.places.ofVertex(size_t(far - s.mesh.p.begin())) +
                            ": " + surfaceReachMessage(reachOf(*far)));
    }
    s.bsdf = readBsdf(r.objectOrEmpty("bsdf"));
    s.emission = spectrum(r, "emission", 0, 0, JsonReader::kUnbounded);
    s.twoSidedEmission = r.boolean("emission_two_sided", false);
    s.name = r.string("name", "surfaces[" + std::to_string(index) + "]");
    if (s.kind == Surface::Kind::Mesh && s.emits()) {
        MeshPlaces places = s.places;
        places.note.clear();  // (the same faces before and after the transform)
        if (const std::string faces = coincidentFaces(s.mesh, places); !faces.empty())
            r.error("file", faces);
    }
    // A closed glass mesh faces outwards whatever its winding or transform, shell by shell (a
    // hollow's inner wall inwards): a dielectric's outside is the side its normal points to.
    if (s.kind == Surface::Kind::Mesh && s.bsdf.type == BsdfType::Dielectric && !s.mesh.p.empty() &&
        !s.faceOutwards())
        r.error("emission", mixedShellsOfAnEmitter(s));
    r.finish();
    return s;
}

/// The surface named by media[i].boundary: a surface's "name" or its index.
int readBoundary(JsonReader& r, const std::vector<Surface>& surfaces, Contents contents) {
    const Json& b = r.raw("boundary");
    int s = -1;
    if (surfaces.empty()) r.error("boundary", "the scene has no surfaces");
    if (b.is_number()) {  // (an index: 0 or 0.0, as integer keys take it; helper 74)
        s = r.integer("boundary", 0, 0, int(surfaces.size()) - 1);
    } else {
        const std::string name = r.string("boundary");
        for (size_t i = 0; i < surfaces.size(); ++i)
            if (surfaces[i].name == name) s = int(i);
        if (s < 0) r.error("boundary", "no surface is named \"" + name + "\"");
    }
    const Surface& sf = surfaces[s];
    if (!sf.closed()) r.error("boundary", sf.name + " is not a closed shape (a mesh or a sphere)");
    if (sf.interiorMedium >= 0) r.error("boundary", sf.name + " already bounds another medium");
    if (sf.kind == Surface::Kind::Mesh && contents == Contents::Load) {  // (the file's contents)
        const std::string& defect = sf.solidity().defect;
        if (!defect.empty()) r.error("boundary", sf.name + ": " + defect);
    }
    const BsdfType t = sf.bsdf.type;
    if (t != BsdfType::Null && t != BsdfType::Dielectric)
        r.error("boundary", sf.name + " has a " + sf.bsdf.name() +
                                " BSDF; a medium boundary must be \"null\" or \"dielectric\"");
    return s;
}

/// The medium media[index] (null for a grid under Contents::Check).
std::unique_ptr<Medium> readMedium(JsonReader r, std::vector<Surface>& surfaces, int index,
                                   Contents contents) {
    const std::string type = r.choice("type", "vdb", {"vdb", "homogeneous"});
    if (r.has("boundary")) {
        const int b = readBoundary(r, surfaces, contents);
        surfaces[b].interiorMedium = index;
        // Outwards, shell by shell, so that crossing against the normal enters the medium.
        if (!surfaces[b].mesh.p.empty() && !surfaces[b].faceOutwards())
            r.error("boundary", mixedShellsOfAnEmitter(surfaces[b]));
    }
    const Spectrum albedo = spectrum(r, "albedo", 1, 0, 1);
    // Absent: isotropic, the phase type's default (and so recorded in scene_resolved).
    const PhaseFunction phase = readPhaseFunction(r.objectOrEmpty("phase"));
    if (type == "homogeneous") {
        const double sigmaT = r.number("sigma_t", 1, 0, 1e12);
        const bool tracking =
            r.choice("estimator", "analytic", {"analytic", "tracking"}) == "tracking";
        MediumShape shape;
        if (r.has("boundary") && !r.has("shape")) {
            shape.type = MediumShape::Type::Everywhere;
            refuseKeysOfType(r, "vdb", kVdbKeys);
            r.finish();
            return std::make_unique<HomogeneousMedium>(shape, sigmaT, albedo, phase, tracking);
        }
        JsonReader sh = r.object("shape");
        const std::string st = sh.choice("type", "box", {"box", "sphere"});
        if (st == "box") {
            shape.type = MediumShape::Type::Box;
            shape.lo = pointInRange(sh, "min", Vec3(-1, -1, -1));
            shape.hi = pointInRange(sh, "max", Vec3(1, 1, 1));
            if ((shape.hi.array() <= shape.lo.array()).any()) sh.error("max", "must exceed min");
        } else {
            shape.type = MediumShape::Type::Sphere;
            shape.center = pointInRange(sh, "center", Vec3::Zero());
            shape.radius = sh.number("radius", 1, 1e-12, 1e12);
        }
        sh.finish();
        refuseKeysOfType(r, "vdb", kVdbKeys);
        r.finish();
        return std::make_unique<HomogeneousMedium>(shape, sigmaT, albedo, phase, tracking);
    }
    VdbMediumDesc d;
    d.file = r.inputFile("file", sceneDir(r));
    d.grid = r.string("grid", d.grid);
    d.densityScale = r.number("density_scale", 1, 0, 1e12);
    d.albedo = albedo;
    d.phase = phase;
    if (r.has("transform")) d.toWorld = readTransform(r.object("transform"));
    d.majorantGrid = r.boolean("majorant_grid", true);
    d.majorantCellVoxels = r.integerOrAuto("majorant_cell", 1, 4096).value_or(0);  // 0: "auto"
    d.bricks = r.choice("lookup", "bricks", {"bricks", "openvdb"}) == "bricks";
    d.decomposition = r.boolean("decomposition", true);
    d.regularTracking = r.boolean("regular_tracking", true);
    refuseKeysOfType(r, "homogeneous", {"sigma_t", "estimator", "shape"});
    r.finish();
    if (contents == Contents::Check) return nullptr;
    return r.readInput("file", [&] { return loadVdbMedium(d); });
}

/// Reads r[key], an array of objects, element by element with read(reader, index); each element's
/// resolved values are recorded into (*resolved)[key][index].
template <typename Read>
void readArray(JsonReader& r, const std::string& key, Json* resolved, Read read) {
    if (!r.has(key)) return;
    const Json& list = r.raw(key);
    if (!list.is_array()) r.error(key, "expected an array of objects");
    // Sized before the readers record into its elements, so none of them moves.
    if (resolved)
        ((*resolved)[key] = Json::array())
            .get_ref<Json::array_t&>()
            .resize(list.size(), Json::object());
    for (size_t i = 0; i < list.size(); ++i) {
        JsonReader element(list[i], r.file(), key + "[" + std::to_string(i) + "]");
        if (resolved) element.recordInto(&(*resolved)[key][i]);
        read(element, i);
    }
}

namespace {
/// Refuses a sweep given for a scene: it was told "axes: unknown key" (helper 122). ("axes" alone
/// decides: --set camera.fov=30 gives a sweep a camera; helper 124.)
void refuseASweep(const Json& doc, const std::string& path) {
    // (a render's statistics have a "scene" too, and were called a sweep)
    if (doc.is_object() && doc.contains("scene_resolved"))
        fail(path, "",
             "a render's statistics (it has \"scene_resolved\"), not a scene: the scene it "
             "rendered is its scene_resolved, which loads from a file of its own in the scene's "
             "folder");
    if (doc.is_object() &&
        (doc.contains("axes") || (doc.contains("scene") && !doc.contains("camera"))))
        fail(path, "",
             "a sweep of shvol batch (it has \"" +
                 std::string(doc.contains("axes") ? "axes" : "scene") +
                 "\"), not a scene: run it with shvol batch");
}
}  // namespace

Scene readScene(const Json& doc, const std::string& path, Json* resolved, Contents contents) {
    Scene scene;
    scene.path = path;
    refuseASweep(doc, path);
    JsonReader r(doc, path, "");
    if (resolved) r.recordInto(&(*resolved = Json::object()));
    scene.camera = readCamera(r.objectOrEmpty("camera"));
    scene.settings = readSettings(r.objectOrEmpty("render"));
    if (r.has("environment"))
        scene.environment = readEnvironment(r.object("environment"), scene.settings, contents);
    else
        r.note("environment", {{"type", "constant"},  // none: black, as readEnvironment has it
                               {"lower_hemisphere_black", false},
                               {"wavelet_coefficients", 0},
                               {"radiance", 0}});
    std::vector<Surface> surfaces;
    std::map<std::string, size_t> names;
    readArray(r, "surfaces", resolved, [&](JsonReader& sr, size_t i) {
        surfaces.push_back(readSurface(sr, i, contents));
        if (!names.emplace(surfaces.back().name, i).second)
            sr.error("name", "\"" + surfaces.back().name + "\" is also the name of surfaces[" +
                                 std::to_string(names[surfaces.back().name]) + "]");
    });
    int bounded = 0;
    readArray(r, "media", resolved, [&](JsonReader& m, size_t i) {
        // The integrator keeps which bounded media a point is inside in 64 bits.
        if (m.has("boundary") && ++bounded > 64)
            m.error("boundary", "more than 64 media have a boundary");
        scene.media.push_back(readMedium(m, surfaces, int(i), contents));
    });
    if (!surfaces.empty() && contents == Contents::Load)
        scene.surfaces = std::make_unique<const SurfaceScene>(std::move(surfaces));
    r.finish();
    return scene;
}

}  // namespace

Scene sceneFromJson(const Json& doc, const std::string& path, Json* resolved) {
    return readScene(doc, path, resolved, Contents::Load);
}

Camera checkScene(const Json& doc, const std::string& path, Json* resolved) {
    return readScene(doc, path, resolved, Contents::Check).camera;
}

Scene loadScene(const std::string& path, const std::vector<std::string>& overrides,
                Json* resolved) {
    return sceneFromJson(sceneDocument(path, overrides), path, resolved);
}

Json sceneDocument(const std::string& path, const std::vector<std::string>& overrides,
                   std::vector<std::string>* unchanged, Json* original,
                   std::vector<int>* removedBy) {
    Json doc = parseJsonFile(path);
    // (before the overrides, which a sweep's axes are: `media[0].albedo` on a sweep given as a
    // sweep's scene was "index 0 of an array the scene does not have"; helper 141)
    refuseASweep(doc, path);
    if (original) *original = doc;
    std::vector<int> by = applyOverrides(doc, overrides, path, unchanged);
    if (removedBy) *removedBy = std::move(by);
    return doc;
}

}  // namespace shvol
