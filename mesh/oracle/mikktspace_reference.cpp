// MikkTSpace, the oracle: a step-by-step implementation of the published
// algorithm (Mikkelsen 2008, "Simulation of Wrinkled Surfaces Revisited",
// section 4.2; the mikktspace.c reference, default 180-degree threshold),
// written for clarity. Each step below is one stage of the reference, in the
// reference's order, with its data kept the way the reference keeps it
// (a list of triangles whose corners name welded "representative" corners).
// The fast implementation (mikktspace.cpp) must reproduce this output bit
// for bit; tests/mesh/tangents_mikktspace_test.cpp checks it.
//
// Differences from the reference that do not change any output:
//  - welding uses an ordered map of exact (position, normal, uv) values
//    instead of a spatial grid; the representative of a welded vertex is its
//    first corner in triangle order (the reference's choice depends on its
//    grid traversal and can only differ in the sign of a zero coordinate,
//    which never changes a result beyond the sign of a zero);
//  - recursion (group flood fill) uses an explicit stack, in the same order;
//  - the degenerate-triangle fix-up looks the first good corner of a welded
//    vertex up in a table instead of a linear search (same corner found).
#include <algorithm>
#include <array>
#include <map>
#include <vector>

#include "mikktspace_common.h"
#include "surfgrad/mesh/mikktspace_reference.h"

namespace sg::mesh {

namespace {

using mikk::Vec3;

// A triangle of the working list (STriInfo).
struct Triangle {
    std::array<int, 3> welded{};             // welded corner ids (representatives)
    std::array<int, 3> vertInFace{};         // which corner of the original face (0..3)
    int face = -1;                           // original face
    int firstOutputCorner = 0;               // where the face's corners start in the output
    std::array<int, 3> neighbor{-1, -1, -1}; // across edge i -> i+1
    std::array<int, 3> group{-1, -1, -1};    // group of corner i
    mikk::FaceDerivatives deriv;
    bool degenerate = false;
    bool quadOneDegenerate = false; // quad whose other triangle is degenerate
};

// A group: triangles around one welded vertex, connected through shared
// edges, with one UV orientation (the "4 rules").
struct Group {
    int vertex = -1; // welded representative
    bool orientPreserving = false;
    std::vector<int> triangles;
};

struct CornerValues {
    Vec3 position;
    Vec3 normal;
    glm::vec2 uv;
};

// Everything the steps share: the input's faces, the triangle list, the
// welded corners, the groups and the corner frames being built.
struct Oracle {
    explicit Oracle(const MikkTSpaceInput& input)
        : in(input), cornerCount(input.cornerVertices.size()),
          faceCount(input.faceSizes.empty() ? cornerCount / 3 : input.faceSizes.size()),
          faceFirst(faceCount), spaces(cornerCount) {
        for (size_t f = 0, c = 0; f < faceCount; c += faceSize(f), ++f) faceFirst[f] = c;
    }

    const MikkTSpaceInput& in;
    size_t cornerCount;
    size_t faceCount;
    std::vector<size_t> faceFirst; // first corner of each face
    std::vector<Triangle> tris;
    std::vector<CornerValues> corners; // per triangle corner; welded ids index it
    int goodCount = 0;                 // good triangles come first (step 4)
    std::vector<Group> groups;
    std::vector<mikk::CornerSpace> spaces; // per output corner

    uint32_t faceSize(size_t f) const { return in.faceSizes.empty() ? 3u : in.faceSizes[f]; }
    CornerValues faceCorner(int face, int k) const {
        const uint32_t v = in.cornerVertices[faceFirst[size_t(face)] + size_t(k)];
        return {mikk::toVec3(in.positions[v]), mikk::toVec3(in.normals[v]), in.uvs[v]};
    }
    Vec3 pos(int w) const { return corners[size_t(w)].position; }
    Vec3 nrm(int w) const { return corners[size_t(w)].normal; }
    glm::vec2 uv(int w) const { return corners[size_t(w)].uv; }
    // Which corner of triangle `tri` is welded vertex `vertex`.
    int cornerAt(const Triangle& tri, int vertex) const {
        return tri.welded[0] == vertex ? 0 : (tri.welded[1] == vertex ? 1 : 2);
    }
    mikk::CornerSpace& space(const Triangle& tri, int corner) {
        return spaces[size_t(tri.firstOutputCorner + tri.vertInFace[size_t(corner)])];
    }
};

// Step 1. Triangle list: triangles as they are, quads split along the
// shorter UV diagonal (shorter position diagonal on a tie, 0-2 on a second
// tie) so the result does not depend on where the quad starts.
void triangles(Oracle& o) {
    for (size_t f = 0; f < o.faceCount; ++f) {
        const uint32_t n = o.faceSize(f);
        if (n != 3 && n != 4) continue;
        Triangle t;
        t.face = int(f);
        t.firstOutputCorner = int(o.faceFirst[f]);
        if (n == 3) {
            t.vertInFace = {0, 1, 2};
            o.tris.push_back(t);
            continue;
        }
        std::array<CornerValues, 4> q;
        for (int k = 0; k < 4; ++k) q[size_t(k)] = o.faceCorner(int(f), k);
        auto uvDist2 = [](glm::vec2 a, glm::vec2 b) {
            const float dx = b.x - a.x, dy = b.y - a.y;
            return dx * dx + dy * dy;
        };
        const float uv02 = uvDist2(q[0].uv, q[2].uv);
        const float uv13 = uvDist2(q[1].uv, q[3].uv);
        bool diagonal02;
        if (uv02 < uv13) {
            diagonal02 = true;
        } else if (uv13 < uv02) {
            diagonal02 = false;
        } else {
            const float p02 = mikk::lengthSquared(mikk::sub(q[2].position, q[0].position));
            const float p13 = mikk::lengthSquared(mikk::sub(q[3].position, q[1].position));
            diagonal02 = !(p13 < p02);
        }
        t.vertInFace = diagonal02 ? std::array<int, 3>{0, 1, 2} : std::array<int, 3>{0, 1, 3};
        o.tris.push_back(t);
        t.vertInFace = diagonal02 ? std::array<int, 3>{0, 2, 3} : std::array<int, 3>{1, 2, 3};
        o.tris.push_back(t);
    }
}

// Step 2. Weld: every triangle corner names the first corner (in triangle
// order) with exactly the same position, normal and uv (== on floats, so
// -0 == +0). Welded ids are indices into `corners`.
void weld(Oracle& o) {
    o.corners.resize(o.tris.size() * 3);
    for (size_t t = 0; t < o.tris.size(); ++t)
        for (int i = 0; i < 3; ++i)
            o.corners[t * 3 + size_t(i)] =
                o.faceCorner(o.tris[t].face, o.tris[t].vertInFace[size_t(i)]);
    std::map<std::array<uint32_t, 8>, int> firstCorner;
    for (size_t c = 0; c < o.corners.size(); ++c) {
        const CornerValues& v = o.corners[c];
        const std::array<uint32_t, 8> key{
            mikk::weldBits(v.position.x), mikk::weldBits(v.position.y),
            mikk::weldBits(v.position.z), mikk::weldBits(v.normal.x),
            mikk::weldBits(v.normal.y),   mikk::weldBits(v.normal.z),
            mikk::weldBits(v.uv.x),       mikk::weldBits(v.uv.y)};
        const int welded = firstCorner.emplace(key, int(c)).first->second;
        o.tris[c / 3].welded[c % 3] = welded;
    }
}

// Step 3. Degenerate triangles: two corners at the same position.
void markDegenerates(Oracle& o) {
    for (Triangle& t : o.tris) {
        const Vec3 p0 = o.pos(t.welded[0]), p1 = o.pos(t.welded[1]), p2 = o.pos(t.welded[2]);
        t.degenerate =
            mikk::exactlyEqual(p0, p1) || mikk::exactlyEqual(p0, p2) || mikk::exactlyEqual(p1, p2);
    }
}

// Step 4. Quads with exactly one degenerate triangle are marked (fixed up
// in step 9); then good triangles move to the front, keeping their order.
void moveDegeneratesLast(Oracle& o) {
    std::vector<Triangle>& tris = o.tris;
    for (size_t t = 0; t + 1 < tris.size();) {
        if (tris[t].face == tris[t + 1].face) {
            if (tris[t].degenerate != tris[t + 1].degenerate) {
                tris[t].quadOneDegenerate = true;
                tris[t + 1].quadOneDegenerate = true;
            }
            t += 2;
        } else {
            ++t;
        }
    }
    std::stable_partition(tris.begin(), tris.end(),
                          [](const Triangle& t) { return !t.degenerate; });
    o.goodCount = int(
        std::count_if(tris.begin(), tris.end(), [](const Triangle& t) { return !t.degenerate; }));
}

// Step 5. Per-triangle derivatives and orientation (eq. 18/19), then the
// two good triangles of a quad are forced to one orientation: the one of
// the good ("not group-with-any") triangle, else of the larger UV area.
void faceDerivatives(Oracle& o) {
    for (int t = 0; t < o.goodCount; ++t) {
        Triangle& tri = o.tris[size_t(t)];
        tri.deriv =
            mikk::faceDerivatives(o.pos(tri.welded[0]), o.pos(tri.welded[1]), o.pos(tri.welded[2]),
                                  o.uv(tri.welded[0]), o.uv(tri.welded[1]), o.uv(tri.welded[2]));
    }
    for (int t = 0; t + 1 < o.goodCount;) {
        Triangle& a = o.tris[size_t(t)];
        Triangle& b = o.tris[size_t(t) + 1];
        if (a.face != b.face) {
            ++t;
            continue;
        }
        if (a.deriv.orientPreserving != b.deriv.orientPreserving) {
            bool keepFirst = false;
            if (b.deriv.groupWithAny) {
                keepFirst = true;
            } else if (mikk::uvAreaTimes2(o.uv(a.welded[0]), o.uv(a.welded[1]),
                                          o.uv(a.welded[2])) >=
                       mikk::uvAreaTimes2(o.uv(b.welded[0]), o.uv(b.welded[1]),
                                          o.uv(b.welded[2]))) {
                keepFirst = true;
            }
            if (keepFirst)
                b.deriv.orientPreserving = a.deriv.orientPreserving;
            else
                a.deriv.orientPreserving = b.deriv.orientPreserving;
        }
        t += 2;
    }
}

// Step 6. Adjacency: sort the undirected edges (smaller welded id, larger
// welded id, triangle); walking the sorted list, an edge without a
// neighbor pairs with the first later edge of the same key that runs the
// other way and has none either.
void adjacency(Oracle& o) {
    struct Edge {
        int lo, hi, tri;
    };
    std::vector<Edge> edges;
    edges.reserve(size_t(o.goodCount) * 3);
    for (int t = 0; t < o.goodCount; ++t)
        for (int i = 0; i < 3; ++i) {
            const int a = o.tris[size_t(t)].welded[size_t(i)];
            const int b = o.tris[size_t(t)].welded[size_t((i + 1) % 3)];
            edges.push_back({std::min(a, b), std::max(a, b), t});
        }
    std::sort(edges.begin(), edges.end(), [](const Edge& x, const Edge& y) {
        return std::tie(x.lo, x.hi, x.tri) < std::tie(y.lo, y.hi, y.tri);
    });
    // Which edge of `tri` joins welded ids {a, b}, and its direction.
    auto edgeOf = [&](int tri, int a, int b, int& from, int& to) {
        const auto& w = o.tris[size_t(tri)].welded;
        if (w[0] == a || w[0] == b) {
            if (w[1] == a || w[1] == b) {
                from = w[0], to = w[1];
                return 0;
            }
            from = w[2], to = w[0];
            return 2;
        }
        from = w[1], to = w[2];
        return 1;
    };
    for (size_t i = 0; i < edges.size(); ++i) {
        const Edge& e = edges[i];
        int fromA, toA;
        const int edgeA = edgeOf(e.tri, e.lo, e.hi, fromA, toA);
        if (o.tris[size_t(e.tri)].neighbor[size_t(edgeA)] != -1) continue;
        for (size_t j = i + 1; j < edges.size() && edges[j].lo == e.lo && edges[j].hi == e.hi;
             ++j) {
            int fromB, toB;
            const int edgeB = edgeOf(edges[j].tri, e.lo, e.hi, fromB, toB);
            if (fromA == toB && toA == fromB &&
                o.tris[size_t(edges[j].tri)].neighbor[size_t(edgeB)] == -1) {
                o.tris[size_t(e.tri)].neighbor[size_t(edgeA)] = edges[j].tri;
                o.tris[size_t(edges[j].tri)].neighbor[size_t(edgeB)] = e.tri;
                break;
            }
        }
    }
}

// Step 7 for one seed: group g (its vertex and orientation set, the seed
// triangle in it) flooded from the seed's corner c through the two edges at
// the vertex. Depth first, left (edge c) before right (edge c-1), as the
// reference's recursion. A group-with-any triangle met for the first time
// (no corner in any group yet) adopts the group's orientation.
void floodGroup(Oracle& o, int g, const Triangle& seed, int c, std::vector<int>& stack) {
    stack.clear();
    // Pushed right first so the left one is visited first.
    if (seed.neighbor[size_t((c + 2) % 3)] >= 0)
        stack.push_back(seed.neighbor[size_t((c + 2) % 3)]);
    if (seed.neighbor[size_t(c)] >= 0) stack.push_back(seed.neighbor[size_t(c)]);
    while (!stack.empty()) {
        const int t = stack.back();
        stack.pop_back();
        Triangle& tri = o.tris[size_t(t)];
        Group& group = o.groups[size_t(g)];
        const int k = o.cornerAt(tri, group.vertex);
        if (tri.group[size_t(k)] != -1) continue; // this group's or another's
        if (tri.deriv.groupWithAny && tri.group[0] == -1 && tri.group[1] == -1 &&
            tri.group[2] == -1)
            tri.deriv.orientPreserving = group.orientPreserving;
        if (tri.deriv.orientPreserving != group.orientPreserving) continue;
        group.triangles.push_back(t);
        tri.group[size_t(k)] = g;
        if (tri.neighbor[size_t((k + 2) % 3)] >= 0)
            stack.push_back(tri.neighbor[size_t((k + 2) % 3)]);
        if (tri.neighbor[size_t(k)] >= 0) stack.push_back(tri.neighbor[size_t(k)]);
    }
}

// Step 7. Groups: for every corner of a good triangle not yet in a group,
// in triangle order, start a group at its welded vertex and flood it to
// triangles with the same orientation (the adoption by group-with-any
// triangles is the only order dependence of the algorithm).
void groups(Oracle& o) {
    std::vector<int> stack;
    for (int f = 0; f < o.goodCount; ++f) {
        for (int i = 0; i < 3; ++i) {
            Triangle& seed = o.tris[size_t(f)];
            if (seed.deriv.groupWithAny || seed.group[size_t(i)] != -1) continue;
            const int g = int(o.groups.size());
            o.groups.push_back({seed.welded[size_t(i)], seed.deriv.orientPreserving, {}});
            seed.group[size_t(i)] = g;
            o.groups[size_t(g)].triangles.push_back(f);
            floodGroup(o, g, seed, i, stack);
        }
    }
}

// Step 8 for one subgroup (sorted member triangles of a group at welded
// vertex `vertex`): the angle-weighted average of its members' projected
// derivatives and magnitudes.
mikk::FrameAccumulator subgroupFrame(const Oracle& o, int vertex, const std::vector<int>& members) {
    mikk::FrameAccumulator frame;
    for (const int t : members) {
        const Triangle& tt = o.tris[size_t(t)];
        if (tt.deriv.groupWithAny) continue; // bad triangles do not contribute
        const int c = o.cornerAt(tt, vertex);
        const Vec3 nc = o.nrm(tt.welded[size_t(c)]);
        const float angle =
            mikk::cornerAngle(o.pos(tt.welded[size_t((c + 2) % 3)]), o.pos(tt.welded[size_t(c)]),
                              o.pos(tt.welded[size_t((c + 1) % 3)]), nc);
        frame.accumulate(angle, mikk::projectToPlane(tt.deriv.vOs, nc),
                         mikk::projectToPlane(tt.deriv.vOt, nc), tt.deriv.magS, tt.deriv.magT);
    }
    frame.finish();
    return frame;
}

// Step 8. Frames. In each group, triangle f's subgroup is every member t
// that is group-with-any (either of them), belongs to the same quad, or
// whose projected derivatives are within the angular threshold of f's
// (cosines > -1 for the default 180 degrees). Each distinct subgroup
// (sorted member list) gets its frame (subgroupFrame); f's corner receives
// it (the two triangles of a quad average theirs in their shared corners).
void frames(Oracle& o) {
    const float thresholdCos = mikk::defaultThresholdCos();
    for (const Group& group : o.groups) {
        const Vec3 n = o.nrm(group.vertex);
        std::vector<std::vector<int>> subgroups;
        std::vector<mikk::FrameAccumulator> subgroupFrames;
        for (const int f : group.triangles) {
            const Triangle& tf = o.tris[size_t(f)];
            const Vec3 fOs = mikk::projectToPlane(tf.deriv.vOs, n);
            const Vec3 fOt = mikk::projectToPlane(tf.deriv.vOt, n);
            std::vector<int> members;
            for (const int t : group.triangles) {
                const Triangle& tt = o.tris[size_t(t)];
                const Vec3 tOs = mikk::projectToPlane(tt.deriv.vOs, n);
                const Vec3 tOt = mikk::projectToPlane(tt.deriv.vOt, n);
                const bool any = tf.deriv.groupWithAny || tt.deriv.groupWithAny;
                const bool sameFace = tf.face == tt.face;
                if (any || sameFace ||
                    (mikk::dot(fOs, tOs) > thresholdCos && mikk::dot(fOt, tOt) > thresholdCos))
                    members.push_back(t);
            }
            std::sort(members.begin(), members.end());
            size_t s = 0;
            while (s < subgroups.size() && subgroups[s] != members) ++s;
            if (s == subgroups.size()) {
                subgroupFrames.push_back(subgroupFrame(o, group.vertex, members));
                subgroups.push_back(members);
            }
            mikk::writeCornerSpace(o.space(tf, o.cornerAt(tf, group.vertex)), subgroupFrames[s],
                                   group.orientPreserving);
        }
    }
}

// Step 9. Degenerate triangles. A corner of a degenerate triangle copies
// the frame of the first good-triangle corner with the same welded vertex
// (or keeps the default frame). The degenerate half of a quad is done
// differently: its corner missing from the good half copies the good
// half's corner at the same position.
void degenerateFrames(Oracle& o) {
    std::vector<int> firstGoodCorner(o.corners.size(), -1);
    for (int j = 3 * o.goodCount - 1; j >= 0; --j)
        firstGoodCorner[size_t(o.tris[size_t(j / 3)].welded[size_t(j % 3)])] = j;
    for (size_t t = size_t(o.goodCount); t < o.tris.size(); ++t) {
        const Triangle& tri = o.tris[t];
        if (tri.quadOneDegenerate) continue;
        for (int i = 0; i < 3; ++i) {
            const int j = firstGoodCorner[size_t(tri.welded[size_t(i)])];
            if (j < 0) continue;
            o.space(tri, i) = o.space(o.tris[size_t(j / 3)], j % 3);
        }
    }
    for (int t = 0; t < o.goodCount; ++t) {
        const Triangle& tri = o.tris[size_t(t)];
        if (!tri.quadOneDegenerate) continue;
        int present = 0;
        for (int i = 0; i < 3; ++i) present |= 1 << tri.vertInFace[size_t(i)];
        const int missing =
            (present & 2) == 0 ? 1 : ((present & 4) == 0 ? 2 : ((present & 8) == 0 ? 3 : 0));
        const Vec3 missingPos = o.faceCorner(tri.face, missing).position;
        for (int i = 0; i < 3; ++i) {
            const int k = tri.vertInFace[size_t(i)];
            if (mikk::exactlyEqual(o.faceCorner(tri.face, k).position, missingPos)) {
                o.spaces[size_t(tri.firstOutputCorner + missing)] =
                    o.spaces[size_t(tri.firstOutputCorner + k)];
                break;
            }
        }
    }
}

// Step 10. Output, per corner of every triangle or quad (other corners
// stay zero).
std::vector<MikkTSpaceFrame> output(const Oracle& o) {
    std::vector<MikkTSpaceFrame> out(o.cornerCount, MikkTSpaceFrame{{0, 0, 0}, 0, {0, 0, 0}, 0, 0});
    if (o.tris.empty()) return out;
    for (size_t f = 0; f < o.faceCount; ++f) {
        const uint32_t n = o.faceSize(f);
        if (n != 3 && n != 4) continue;
        for (uint32_t k = 0; k < n; ++k)
            out[o.faceFirst[f] + k] = mikk::toFrame(o.spaces[o.faceFirst[f] + k]);
    }
    return out;
}

} // namespace

std::vector<MikkTSpaceFrame> mikktspaceReferenceFrames(const MikkTSpaceInput& in) {
    mikk::validateInput(in);
    Oracle o(in);
    triangles(o); // step 1
    if (o.tris.empty()) return output(o);
    weld(o);                // step 2
    markDegenerates(o);     // step 3
    moveDegeneratesLast(o); // step 4
    faceDerivatives(o);     // step 5
    adjacency(o);           // step 6
    groups(o);              // step 7
    frames(o);              // step 8
    degenerateFrames(o);    // step 9
    return output(o);       // step 10
}

} // namespace sg::mesh
