// surfgrad normal-map toolkit: the height-field-correct operations of
// Loviscach, "Care and Feeding of Normal Vectors" (GDC 2008), "Feeding" and
// "Care", applied to whole images, next to the plain image operations
// ("naive") they replace. The per-texel math is the shared shader source
// (shaders/sg/deriv_edit.glsl, surfgrad.glsl, lean.glsl through
// surfgrad/bump/core.h); this library adds what only whole images need: file
// I/O, encodings, Poisson integration, resampling, MIP chains and the
// rasterised tangent frames of a mesh. `surfgrad normalmap ...` is its CLI
// (apps/surfgrad/cmd_normalmap.cpp); docs/normalmap.md shows every op.
//
// Conventions (every function below):
//  - Grids are row-major with row 0 the BOTTOM row of the image (files store
//    the top row first; readImage/writeImage flip). Texel (i, j) is centred
//    at (u, v) = (i + 0.5, j + 0.5) in texel units: u right, v up, the
//    texture coordinate (s, t) = (u / W, v / H).
//  - A slope ("derivative", DerivField) is d = (dh/du, dh/dv) of a height h,
//    with h, u and v all measured in texels: dimensionless, w.r.t. +u and +v
//    whatever the file's green convention. It is what a tangent-space normal
//    map stores, n = normalize(-d.x, -d.y, 1) (Loviscach, "Normal in Short
//    Form"; Mikkelsen 2019, eq. 4).
//  - Heights (ScalarField used as a height) are in texels. Heights the
//    library integrates from slopes are measured from their lowest texel
//    (min = 0): a normal map does not know the absolute level, and operations
//    that need h (modulate, curves, masked blend) use this one.
//  - Tiling: Wrap::Repeat treats the image as one period of a tiling
//    texture (differences, sampling and integration wrap around);
//    Wrap::Clamp as a finite patch (one-sided differences across the
//    border; integration with a Neumann boundary: the height mirrored at
//    the border).
//  - Inputs are finite: readImage refuses non-finite texels, and every op
//    returns finite slopes and unit normals for finite inputs (flat,
//    extreme and horizon normals included: listing 4 clamps slopes to
//    +-128).
//  - Errors in untrusted input (files, channel counts, curve and warp
//    text) throw sg::io::InputError naming file, element and reason.
//    Preconditions stated at a declaration (grids of one size, a UV set the
//    mesh has) are contracts (surfgrad/base/contract.h): the CLI checks the
//    files it reads before calling.
//    Long operations report progress through a Progress callback and run
//    on TBB's task arena (tbb::global_control limits the threads).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "surfgrad/image/image.h"

namespace sg::mesh {
struct RenderMesh;
}

namespace sg::normalmap {

// ---------------------------------------------------------------------------
// Grids

template <class T>
struct Grid {
    int width = 0, height = 0;
    std::vector<T> v; // width * height values, row 0 at the bottom

    Grid() = default;
    Grid(int w, int h, T fill = T{}) : width(w), height(h), v(size_t(w) * size_t(h), fill) {}
    size_t size() const { return v.size(); }
    T& at(int i, int j) { return v[size_t(j) * size_t(width) + size_t(i)]; }
    const T& at(int i, int j) const { return v[size_t(j) * size_t(width) + size_t(i)]; }
};

using DerivField = Grid<glm::vec2>;  // slopes (dh/du, dh/dv), see above
using NormalField = Grid<glm::vec3>; // unit tangent-space normals, +y along +v
using ScalarField = Grid<float>;     // heights (texels), masks, gains

enum class Wrap { Clamp, Repeat };

// Progress of a long operation: called with a fraction in [0, 1] from the
// calling thread (never concurrently). May be empty.
using Progress = std::function<void(double fraction)>;

// ---------------------------------------------------------------------------
// Image files: read by the guarded decoder of surfgrad/image/image_decode.h (PNG,
// JPEG, OpenEXR, TIFF, Radiance HDR, TGA; headers checked against the file
// before anything is allocated), written by the image writer of
// surfgrad/image/image_write.h (atomically; rows flipped to the file's top-first
// order)

enum class SampleType { U8, U16, Half, Float };

// The toolkit's images are the image module's (surfgrad/image/image.h): raw
// channel values, no colour conversion (normal maps are data); integer
// samples become [0, 1], float samples are kept (Image::isFloat says
// which). Row 0 is the bottom row; at(i, j, c) is texel (i, j)'s channel c.
using Image = sg::image::Image;

// Largest side and texel count readImage accepts (larger files are refused
// before decoding).
inline constexpr int kMaxImageSide = 16384;
inline constexpr size_t kMaxImageTexels = size_t(1) << 28;

// Reads an image. Throws InputError when the file is missing or unreadable,
// its header promises more than the file holds, its size is 0 or beyond the
// limits, it has no channels or more than 64, the decoded image as float
// would not fit in sg::image::defaultMemoryBudget(), it cannot be decoded,
// or a texel is not finite (element "pixel (x, y) channel c" in file
// coordinates, row 0 at the top). `sampleType` receives the file's.
// Alpha is read as stored (never premultiplied into the colour channels).
Image readImage(const std::filesystem::path& path, SampleType* sampleType = nullptr);

// Writes atomically (sg::io::writeAtomically) with the given sample type:
// .png (U8, U16), .tga (U8), .tif/.tiff (U8, U16, Half, Float), .exr (Half,
// Float). Non-finite texels are written as 0; integer types clamp to
// [0, 1]. The fourth channel is marked alpha (unassociated: colour is
// never divided by it); the colour space is tagged "Linear". Throws
// InputError for an unsupported extension/type pair (checkWritable) or a
// failed write. `attributes` become string metadata (e.g.
// "surfgrad:encoding").
void writeImage(const std::filesystem::path& path, const Image& image, SampleType type,
                const std::vector<std::pair<std::string, std::string>>& attributes = {});

// Throws InputError (path, "", reason) when writeImage could not write
// samples of `type` as path's extension: commands check their outputs
// with it before long work starts.
void checkWritable(const std::filesystem::path& path, SampleType type);

// The sample type an output gets by default: U8 for .png/.tga, U16 for
// .tif/.tiff, Float for .exr; an integer type is replaced by Float when
// `needFloat` (the data is not in [0, 1], e.g. raw heights or slopes).
SampleType defaultSampleType(const std::filesystem::path& path, bool needFloat);

// Parses "8", "16", "half", "float" (CLI --bits). Throws InputError.
SampleType parseSampleType(std::string_view text);

// ---------------------------------------------------------------------------
// Encodings of a tangent-space map in an image

enum class Encoding {
    Rgb,    // xyz in channels 0-2 as 0.5 n + 0.5 (any sample type)
    Rg,     // xy in channels 0-1 as 0.5 n + 0.5, z reconstructed (two-channel)
    Ag,     // x in alpha (channel 3), y in channel 1 (DXT5nm / BC3n layout)
    Signed, // xyz in channels 0-2 as stored (float files only)
    Deriv,  // slopes (dh/du, dh/dv) in channels 0-1: as stored in float files,
            // as 0.5 + 0.5 d / derivRange in integer files
};

// Green convention: Gl when +green points to +v (up; OpenGL, glTF, Blender),
// Dx when it points down (DirectX, Unreal). Derivative maps follow it too.
enum class Green { Gl, Dx };

struct MapFormat {
    Encoding encoding = Encoding::Rgb;
    Green green = Green::Gl;
    // Slope stored at full scale (value 1 or 0) by integer derivative maps.
    float derivRange = 8.0f;
};

// Parses "rgb", "rg", "ag", "signed", "deriv" and "gl", "dx". Throw InputError.
Encoding parseEncoding(std::string_view text);
Green parseGreen(std::string_view text);
std::string_view encodingName(Encoding e);

// The sample type of a map output in `format`: parseSampleType(bits), or
// defaultSampleType when bits is empty (float for signed normals). Throws
// InputError naming `path` when signed normals would be written as integer
// samples or to .png/.tga (element "encoding"; they hold negative values)
// and when the extension cannot hold the type (checkWritable).
SampleType mapSampleType(const std::filesystem::path& path, const MapFormat& format,
                         std::string_view bits);

// The slopes of a tangent-space map: normal encodings through listing 4
// (sgTspaceNormalToDeriv: from x and y, |d| <= 128 per component), derivative
// maps directly. Throws InputError (file, "channels") when the image has too
// few channels for the encoding, or Signed/Deriv-as-stored on integer data
// is requested where it cannot be represented.
DerivField decodeSlopes(const Image& image, const MapFormat& format, const std::string& file);
// The unit normals the image holds (z from the file for Rgb/Signed,
// reconstructed as sqrt(max(0, 1 - x^2 - y^2)) for Rg/Ag, normalize(-d, 1)
// for Deriv), renormalised; what naive image operations work on. A texel
// with no direction (all zero) becomes (0, 0, 1).
NormalField decodeNormals(const Image& image, const MapFormat& format, const std::string& file);

// Image of the given encoding (channels: 3 for Rgb/Signed, 2 for Rg/Deriv,
// 4 for Ag with x in alpha) from slopes (normals by sgDerivToTspaceNormal)
// or from unit normals (slopes by listing 4). `isFloat` selects the value
// mapping of Deriv.
Image encodeSlopes(const DerivField& d, const MapFormat& format, bool isFloat);
Image encodeNormals(const NormalField& n, const MapFormat& format, bool isFloat);

// Slopes <-> unit normals, per texel through the shared functions.
NormalField normalsFromSlopes(const DerivField& d);
DerivField slopesFromNormals(const NormalField& n);

// A scalar field from one channel of an image (channel < 0: Rec. 709
// luminance of channels 0-2 when there are 3 or more, else channel 0),
// times `scale`. Throws InputError when the channel does not exist.
ScalarField scalarFromImage(const Image& image, int channel, float scale, const std::string& file);
// One-channel image of (value - offset) * scale.
Image imageFromScalar(const ScalarField& s, float offset, float scale, bool isFloat);

// ---------------------------------------------------------------------------
// Height <-> slopes ("Birth of Normal Vectors")

// Central differences of scale * h (scale: texels of height per unit of the
// field's value), sgHeightDerivCentral; Clamp uses one-sided differences
// (h(1) - h(0), h(N-1) - h(N-2)) across the border rows and columns.
DerivField fromHeight(const ScalarField& h, float scale, Wrap wrap);

// The height whose central-difference slopes are closest (least squares) to
// `d`: the Poisson solve, exact on slopes that fromHeight made. Repeat: DFT
// of the periodic grid; Clamp: DCT/DST, the mirrored (Neumann) extension.
// Per frequency the normal equations are diagonal; frequencies the central
// difference cannot see (the mean, and the Nyquist rows/columns of even
// periodic sizes) get 0. Near-Nyquist frequencies are amplified by up to
// 1 / sin(pi / N) (a slope field that is not integrable there gives
// texel-scale ripples in h, not in its slopes). Result measured from its
// lowest texel (min = 0). Cost: a few 2D FFTs of the grid in double
// (~16 bytes per texel), O(N log N) for any size (Bluestein for sizes that
// are not powers of two).
ScalarField toHeight(const DerivField& d, Wrap wrap, const Progress& progress = {});

// ---------------------------------------------------------------------------
// The "Feeding" operations on slopes (shared functions per texel)

// "Scaling": the slopes of alpha h (sgDerivScale). alpha = -1 inverts,
// alpha = 2 doubles the slopes and never turns a normal inward.
DerivField scale(const DerivField& d, float alpha);
// "Adding and Blending": the slopes of wa hA + wb hB (sgDerivAdd).
// Every op taking several grids requires them to have one size.
DerivField add(const DerivField& a, float wa, const DerivField& b, float wb);
// Blending with a mask m in [0, 1] (any values accepted): the slopes of
// (1 - m) hA + m hB (sgDerivMaskBlend, product rule), with the mask's
// slopes by central differences.
DerivField blend(const DerivField& a, const ScalarField& ha, const DerivField& b,
                 const ScalarField& hb, const ScalarField& mask, Wrap wrap);
// "Modulation": the slopes of h g for a gain field g (sgDerivModulate);
// g's slopes by central differences.
DerivField modulate(const DerivField& d, const ScalarField& h, const ScalarField& gain, Wrap wrap);

// "Curves": a height curve f applied to the normalised elevation
// x = (h - hMin) / (hMax - hMin) of the map's heights; the slopes become
// f'(x) d ("Curves (3)", sgDerivCurve), i.e. the new height is
// (hMax - hMin) f(x). Either the paper's boost f'(x) = 1 / (1 + P (x - H)^2)
// ("Curves (5)", sgCurveBoostSlope) or a curve through points (x_k, y_k),
// x strictly increasing in [0, 1], interpolated by monotone cubic Hermite
// segments (Fritsch-Carlson slopes; sgCurveHermite), continuous f'.
struct Curve {
    bool boost = true;
    float boostP = 0.0f, boostH = 0.5f;
    std::vector<glm::vec2> points; // x strictly increasing (boost == false)
    std::vector<float> slopes;     // df/dx at each point (Fritsch-Carlson)
    // f'(x).
    float slopeAt(float x) const;
};
// The boost curve of the paper.
Curve boostCurve(float P, float H);
// A curve through points given as text: "x,y x,y ..." (whitespace or ';'
// between points), 2 to 64 points, finite, x strictly increasing within
// [0, 1] and at least 1e-4 apart. Throws InputError(source, "point k",
// reason). Fritsch-Carlson keeps monotone data monotone.
Curve parseCurvePoints(std::string_view text, const std::string& source);
DerivField applyCurve(const DerivField& d, const ScalarField& h, const Curve& curve);

// "Deformation": the map h(s(u, v), t(u, v)) for a warp of normalised
// texture coordinates (s, t) = warp(u / W, v / H); slopes are sampled
// bilinearly at the warped point and mapped by the warp's Jacobian
// (sgDerivDeform: d' = J^T d, J converted to texel units).
struct Warp {
    enum class Kind {
        Sine,   // "Deformation (4)": s = u, t = v + a sin(b u) (sgSineWarpJacobian)
        Rotate, // rotation by a degrees about (0.5, 0.5): the Jacobian is the rotation
    };
    Kind kind = Kind::Sine;
    float a = 0.0f, b = 0.0f;
};
// "sine:A,B" or "rotate:DEG". Throws InputError.
Warp parseWarp(std::string_view text);
DerivField deform(const DerivField& d, const Warp& warp, Wrap wrap);

// ---------------------------------------------------------------------------
// The naive comparison: what image editors do to the encoded normals
// (per-channel lerp/add/resample, then renormalise). Not height-field
// correct; kept as the baseline the docs and tests measure against.
namespace naive {
// normalize(alpha n + (1 - alpha) (0, 0, 1)) (Loviscach, "Scaling (1)").
NormalField scale(const NormalField& n, float alpha);
// normalize(flat + wa (nA - flat) + wb (nB - flat)), flat = (0, 0, 1).
NormalField add(const NormalField& a, float wa, const NormalField& b, float wb);
// normalize((1 - m) nA + m nB).
NormalField blend(const NormalField& a, const NormalField& b, const ScalarField& mask);
// normalize(g n + (1 - g) flat): the gain as an opacity.
NormalField modulate(const NormalField& n, const ScalarField& gain);
// The naive scale with alpha = f'(x) per texel (x as in applyCurve).
NormalField applyCurve(const NormalField& n, const ScalarField& h, const Curve& curve);
// Bilinear resampling of the normals at the warped point, renormalised.
NormalField deform(const NormalField& n, const Warp& warp, Wrap wrap);
// Forward differences h(u + 1) - h(u) (listing 9's 3-tap), half a texel off.
DerivField fromHeight(const ScalarField& h, float scale, Wrap wrap);
// Path integration: cumulative sums of d.y up the first column, then of
// d.x along each row; min = 0.
ScalarField toHeight(const DerivField& d);
// Slopes read as -n.xy (the small-angle reading of a normal map).
DerivField slopesFromNormals(const NormalField& n);
} // namespace naive

// ---------------------------------------------------------------------------
// Object space ("convert ... given a mesh")

// Per-texel tangent frames of a mesh's UV layout: each triangle of UV set
// `uvSet` is rasterised (texel centres, top-left rule) and its vertex normal
// and MikkTSpace tangent (xyz, sign w; RenderMesh::tangents, generated when
// absent or for another set) interpolated linearly and NOT normalised
// (Mikkelsen 2019, section 2.2: the mikktspace basis uses the interpolated
// vectors). Texels outside every triangle are filled from the nearest
// covered texel up to `dilateTexels` away (covered = 2 there), else stay
// uncovered (0). Where UV islands overlap the last triangle wins; parts of
// triangles outside [0, 1]^2 are clipped (not wrapped). Preconditions: the
// mesh has vertex normals, uvSet indexes its UV sets, and MikkTSpace's input
// conditions hold (sg::mesh::tangentInputProblem(mesh, MikkTSpace, uvSet)
// is empty) when it has no tangents for that set.
struct TexelFrames {
    Grid<glm::vec3> normal;
    Grid<glm::vec4> tangent;
    Grid<uint8_t> covered; // 1 inside a triangle, 2 dilated, 0 none
};
TexelFrames rasterizeFrames(const sg::mesh::RenderMesh& mesh, int uvSet, int width, int height,
                            int dilateTexels);
// Tangent-space slopes -> unit object-space normals through the shared
// framework: sgMikktsBasis, sgSurfgradFromTBN, sgResolve. Uncovered texels
// get (0, 0, 0) (encoded as mid-grey).
NormalField objectFromTangent(const DerivField& d, const TexelFrames& frames);
// Object-space normals -> tangent-space slopes: sgSurfgradFromPerturbedNormal
// gives the surface gradient, whose coordinates in the mikktspace basis
// are the slopes (2x2 solve in the tangent plane). Uncovered texels and
// degenerate frames get slope 0. Object normals below the base's horizon
// are clamped by listing 7 (large but finite slopes).
DerivField tangentFromObject(const NormalField& objectNormals, const TexelFrames& frames);
namespace naive {
// The common shader shortcut: the interpolated frame normalised (t, n, and
// b = sign(w) normalize(n x t)) and used as a rotation, ignoring the
// mikktspace basis scaling of section 2.2; its inverse is the transpose.
NormalField objectFromTangent(const NormalField& n, const TexelFrames& frames);
NormalField tangentFromObject(const NormalField& objectNormals, const TexelFrames& frames);
} // namespace naive

// ---------------------------------------------------------------------------
// MIP chains for antialiasing ("Care: Antialiasing")
//
// File layout (`surfgrad normalmap mips IN -o OUT.exr --lean|--toksvig`): one
// OpenEXR file, tiled 64 x 64, with a full MIP chain (OpenEXR MIPMAP_LEVELS,
// round-down: level k is max(1, floor(W / 2^k)) x max(1, floor(H / 2^k)),
// down to 1 x 1), 32-bit float channels, rows top first as in every image
// file (the +v direction is up). Level k+1 is the box filter of level k:
// each texel averages the level-k texels its footprint covers, weighted by
// the overlap (exact 2x2 means for even sizes), so every level holds the
// averages of level-0 values over its footprint; values are not rescaled
// per level (slopes are dimensionless).
//  LEAN ("surfgrad:layout" = "lean1"), 5 channels:
//    "dx", "dy"            E[d]: mean slope w.r.t. +u, +v (OpenGL green)
//    "dxx", "dyy", "dxy"   E[d.x^2], E[d.y^2], E[d.x d.y]
//  The renderer reads B = (dx, dy), M = (dxx, dyy, dxy) at its filtered
//  footprint and gets the slope covariance by sgLeanCovariance(B, M); the
//  mean normal is sgDerivToTspaceNormal(B).
//  Toksvig ("surfgrad:layout" = "toksvig1"), 4 channels:
//    "nx", "ny", "nz"      E[n]: average unit normal (length <= 1), +y up
//    "s2"                  sgToksvigVariance(E[n]) at this level
//  The renderer scales a Blinn-Phong exponent p by sgToksvigFactor(s2, p);
//  filtering (nx, ny, nz) and recomputing s2 is also valid.
//  Naive ("surfgrad:layout" = "normal1"), 3 channels "nx", "ny", "nz": the
//  renormalised average normal (what a plain MIP chain of the map holds).
// Attributes: "surfgrad:layout", "surfgrad:wrap" ("repeat"/"clamp", how the
// source was meant to tile).

inline constexpr const char* kLeanLayout = "lean1";
inline constexpr const char* kToksvigLayout = "toksvig1";
inline constexpr const char* kNaiveMipLayout = "normal1";

// The level sizes of the chain above.
std::vector<std::pair<int, int>> mipSizes(int width, int height);
// Box-filter reduction of an image to width x height (overlap weights).
Image boxReduce(const Image& src, int width, int height);
// Level 0 of each layout (channels as listed above); mipChain() makes the rest.
Image leanLevel0(const DerivField& d);
Image toksvigLevel0(const NormalField& n);
Image naiveMipLevel0(const NormalField& n);
std::vector<Image> mipChain(Image level0, const Progress& progress = {});
// Recomputes "s2" (channel 3) of Toksvig levels from their averaged normals,
// and renormalises naive levels.
void finishToksvig(std::vector<Image>& levels);
void finishNaiveMips(std::vector<Image>& levels);
// Writes a chain in the layout above: one tiled OpenEXR file with MIP
// levels (sg::image::writeMipChainFile), float samples, non-finite texels
// as 0. `levels` is the full chain of mipSizes(level 0) (a caller bug
// otherwise). Throws InputError for a path not ending in .exr, channel
// names that do not match, or a failed write.
void writeMipChain(const std::filesystem::path& path, const std::vector<Image>& levels,
                   const std::vector<std::string>& channelNames, const std::string& layout,
                   Wrap wrap);
// The channel names of a layout in the order above (empty for another).
// OpenEXR stores channels sorted by name: readers look them up by name.
std::vector<std::string> mipChannelNames(std::string_view layout);
// Reads every level of such a file (for tests and the renderer), channels
// in the layout's order (the file's order for an unknown layout), with the
// channel names and the layout attribute. Throws InputError when a layout's
// channel is missing.
std::vector<Image> readMipChain(const std::filesystem::path& path,
                                std::vector<std::string>* channelNames = nullptr,
                                std::string* layout = nullptr);

// ---------------------------------------------------------------------------
// Shading preview (for docs/before-after images)

// Lambert shading of tangent-space normals lit from `lightDir` (tangent
// space, normalised inside), grey albedo, as a 3-channel [0, 1] image:
// 0.08 + 0.85 max(0, n . l). n is used as given: an unnormalised average
// normal (Toksvig) gives the average of its texels' Lambert terms where
// they all face the light.
Image shade(const NormalField& n, glm::vec3 lightDir);

} // namespace sg::normalmap
