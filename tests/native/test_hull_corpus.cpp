// Convex shapes as animators' scenes give them (Blender's default CONVEX_HULL on lathed bodies and
// UV spheres with float coordinates and seams, Cell Fracture pieces, near-degenerate clouds,
// passive hulls whose origin lies off their surface), their refinement ghosts included: every
// convex geom handed to ODE passes ODE's own checks, which print to standard output otherwise.
#include <gtest/gtest.h>
#include <ode/ode.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "SceneFixtures.h"
#include "sim/CompiledScene.h"
#include "sim/OdeWorld.h"
#include "sim/WorldSimulator.h"

namespace mwb {
namespace {

constexpr double kPi = 3.14159265358979323846;

void push(std::vector<double>& xyz, double x, double y, double z) {
    // Blender stores mesh coordinates as 32-bit floats.
    xyz.insert(xyz.end(), {double(float(x)), double(float(y)), double(float(z))});
}

// A body of revolution as Blender's Spin or Screw makes it: every ring closes with a duplicate of
// its first vertex (the seam), and the profile ends on the axis.
std::vector<double> lathed_bottle(int segments, int rings) {
    std::vector<double> xyz;
    push(xyz, 0, 0, 0);
    for (int k = 0; k <= rings; ++k) {
        const double z = 0.3 * k / rings;
        const double shoulder = std::cos(std::min(1.0, std::max(0.0, (z - 0.15) / 0.08)) * kPi / 2);
        const double r = z < 0.01 ? 0.04 + z : 0.015 + 0.035 * shoulder * shoulder;
        for (int i = 0; i <= segments; ++i)
            push(xyz, r * std::cos(2 * kPi * i / segments), r * std::sin(2 * kPi * i / segments), z);
    }
    push(xyz, 0, 0, 0.3);
    return xyz;
}

std::vector<double> uv_sphere(double radius, int segments, int rings) {
    std::vector<double> xyz;
    push(xyz, 0, 0, radius);
    push(xyz, 0, 0, -radius);
    for (int j = 1; j < rings; ++j)
        for (int i = 0; i < segments; ++i) {
            const double theta = kPi * j / rings, phi = 2 * kPi * i / segments;
            push(xyz, radius * std::sin(theta) * std::cos(phi), radius * std::sin(theta) * std::sin(phi),
                 radius * std::cos(theta));
        }
    return xyz;
}

// A Cell Fracture piece: a cube cut by random planes through points near its centre, the cell's
// corners found by brute force (every triple of planes), many of them slivers.
std::vector<double> fractured_cell(std::mt19937& rng) {
    std::uniform_real_distribution<double> unit(-1, 1);
    std::vector<std::array<double, 4>> planes;
    for (int a = 0; a < 3; ++a)
        for (double side : {-1.0, 1.0}) {
            std::array<double, 4> p{0, 0, 0, 0.5};
            p[a] = side;
            planes.push_back(p);
        }
    for (int k = 0; k < 5; ++k) {
        Vec3 n{unit(rng), unit(rng), unit(rng)};
        n = scale(n, 1 / norm(n));
        planes.push_back({n[0], n[1], n[2], 0.05 + 0.2 * std::fabs(unit(rng))});
    }
    std::vector<double> xyz;
    for (size_t i = 0; i < planes.size(); ++i)
        for (size_t j = i + 1; j < planes.size(); ++j)
            for (size_t k = j + 1; k < planes.size(); ++k) {
                const Vec3 a{planes[i][0], planes[i][1], planes[i][2]}, b{planes[j][0], planes[j][1], planes[j][2]},
                    c{planes[k][0], planes[k][1], planes[k][2]};
                const double det = dot(a, cross(b, c));
                if (std::fabs(det) < 1e-9) continue;
                const Vec3 x = scale(add(add(scale(cross(b, c), planes[i][3]), scale(cross(c, a), planes[j][3])),
                                         scale(cross(a, b), planes[k][3])),
                                     1 / det);
                bool inside = true;
                for (const auto& p : planes) inside = inside && dot({p[0], p[1], p[2]}, x) <= p[3] + 1e-9;
                if (inside) push(xyz, x[0], x[1], x[2]);
            }
    return xyz;
}

// A piece of a Cell Fracture wall as Blender 3.4's add-on cut it (tests/fidelity's fracture_wall,
// Wall_cell.002), every corner listed twice, in float coordinates.
std::vector<double> cell_fracture_piece() {
    return {
        -0.08275861293077469, -0.10000000149011612, 0.15674737095832825,
        0.12410428375005722, -0.10000000149011612, 0.1569368839263916,
        0.08255946636199951, 0.10000000149011612, 0.156813383102417,
        0.1241069883108139, 0.10000000149011612, 0.15685144066810608,
        0.12404609471559525, -0.10000000149011612, -0.17591454088687897,
        0.12409529834985733, 0.10000000149011612, 0.08999965339899063,
        0.12402354925870895, -0.10000000149011612, -0.19224309921264648,
        0.12370556592941284, 0.10000000149011612, -0.19224309921264648,
        -0.12383439391851425, -0.10000000149011612, 0.1566590964794159,
        -0.124293752014637, 0.10000000149011612, 0.1563687026500702,
        -0.12380602955818176, -0.10000000149011612, -0.1754487156867981,
        -0.12428808212280273, 0.10000000149011612, 0.08995889872312546,
        -0.12378167361021042, -0.10000000149011612, -0.19224309921264648,
        -0.12387875467538834, 0.10000000149011612, -0.19224309921264648,
        -0.08275861293077469, -0.10000000149011612, 0.15674737095832825,
        0.12410428375005722, -0.10000000149011612, 0.1569368839263916,
        0.08255946636199951, 0.10000000149011612, 0.156813383102417,
        0.1241069883108139, 0.10000000149011612, 0.15685144066810608,
        0.12404609471559525, -0.10000000149011612, -0.17591454088687897,
        0.12402354925870895, -0.10000000149011612, -0.19224309921264648,
        0.12370556592941284, 0.10000000149011612, -0.19224309921264648,
        -0.12383439391851425, -0.10000000149011612, 0.1566590964794159,
        -0.124293752014637, 0.10000000149011612, 0.1563687026500702,
        -0.12380602955818176, -0.10000000149011612, -0.1754487156867981,
        -0.12428808212280273, 0.10000000149011612, 0.08995889872312546,
        0.12409529834985733, 0.10000000149011612, 0.08999965339899063,
        -0.12378167361021042, -0.10000000149011612, -0.19224309921264648,
        -0.12387875467538834, 0.10000000149011612, -0.19224309921264648};
}

Body hull_body(const std::string& name, std::vector<double> points, const Vec3& location,
               BodyType type = BodyType::Active) {
    Body b;
    b.name = name;
    b.type = type;
    b.shape.type = ShapeType::ConvexHull;
    b.shape.vertices_m = std::move(points);
    b.initial.location = location;
    return b;
}

Scene corpus() {
    Scene s;
    s.world.frame_end = 49;
    s.bodies.push_back(fixtures::ground());
    for (int segments : {16, 24, 32, 48})
        s.bodies.push_back(hull_body("Bottle" + std::to_string(segments), lathed_bottle(segments, 40), {0, 0, 0}));
    s.bodies.push_back(hull_body("Sphere", uv_sphere(1.0, 32, 16), {0, 3, 1}));
    s.bodies.push_back(hull_body("Pebble", uv_sphere(0.013, 32, 16), {0, 5, 1}));
    std::mt19937 rng(11);
    for (int k = 0; k < 12; ++k) s.bodies.push_back(hull_body("Cell" + std::to_string(k), fractured_cell(rng), {3, 0, 1}));
    s.bodies.push_back(hull_body("Wall_cell.002", cell_fracture_piece(), {3, 1, 1}));
    // A needle, a sliver and a flat square (Blender accepts a hull of a plane).
    s.bodies.push_back(hull_body("Needle", {0, 0, 0, 2, 0, 0, 1, 1e-3, 0, 1, 0, 1e-3, 2, 1e-3, 1e-3}, {5, 0, 1}));
    s.bodies.push_back(hull_body("Sliver", {0, 0, 0, 1, 0, 0, 0, 1, 0, 0.3, 0.3, 1e-4}, {6, 0, 1}));
    s.bodies.push_back(hull_body("Tile", {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}, {7, 0, 1}));
    // Passive hulls whose object origin is on their surface or far outside it.
    std::vector<double> stair;
    for (double x : {0.0, 1.0})
        for (double y : {0.0, 2.0})
            for (double z : {0.0, 0.2}) push(stair, x + 4, y + 4, z);
    s.bodies.push_back(hull_body("Step", stair, {0, 0, 0}, BodyType::Passive));
    s.bodies.push_back(hull_body("Bowl", lathed_bottle(16, 12), {0, 8, 0}, BodyType::Passive));
    return s;
}

// What ODE prints (to standard output) while it builds a geom for each convex part.
std::string ode_output_for(const CompiledScene& scene, bool ghosts) {
    initialize_ode_once();
    std::fflush(stdout);
    std::FILE* capture = std::tmpfile();
    const int saved = ::dup(STDOUT_FILENO);
    ::dup2(::fileno(capture), STDOUT_FILENO);
    dSpaceID space = dSimpleSpaceCreate(nullptr);
    for (const CompiledBody& body : scene.bodies())
        for (const CollisionPart& part : ghosts ? body.ghost_parts : body.parts)
            if (part.kind == PartKind::Convex)
                dCreateConvex(space, part.convex_planes.data(), part.convex_plane_count, part.convex_points.data(),
                              part.convex_point_count, part.convex_polygons.data());
    dSpaceDestroy(space);
    std::fflush(stdout);
    ::dup2(saved, STDOUT_FILENO);
    ::close(saved);
    std::string text;
    std::rewind(capture);
    for (int c; (c = std::fgetc(capture)) != EOF;) text.push_back(static_cast<char>(c));
    std::fclose(capture);
    return text;
}

TEST(HullCorpus, OdeAcceptsEveryConvexShapeAndEveryGhostSilently) {
    const CompiledScene scene(corpus(), SimulationParameters{});
    size_t convex = 0;
    for (const CompiledBody& body : scene.bodies())
        for (const CollisionPart& part : body.ghost_parts) convex += part.kind == PartKind::Convex;
    ASSERT_GE(convex, 20u) << "the corpus must reach ODE as general convex geoms";
    EXPECT_EQ(ode_output_for(scene, false), "");
    EXPECT_EQ(ode_output_for(scene, true), "");
}

TEST(HullCorpus, EveryFaceHasTheGeomOriginInsideAndStartsOnACounterClockwiseCorner) {
    const CompiledScene scene(corpus(), SimulationParameters{});
    for (size_t b = 0; b < scene.bodies().size(); ++b)
        for (const auto* parts : {&scene.bodies()[b].parts, &scene.bodies()[b].ghost_parts})
            for (const CollisionPart& part : *parts) {
                if (part.kind != PartKind::Convex) continue;
                const unsigned* polygon = part.convex_polygons.data();
                for (unsigned f = 0; f < part.convex_plane_count; ++f, polygon += polygon[0] + 1) {
                    auto corner = [&](int k) {
                        const double* p = &part.convex_points[3 * polygon[1 + k]];
                        return Vec3{p[0], p[1], p[2]};
                    };
                    const Vec3 n{part.convex_planes[4 * f], part.convex_planes[4 * f + 1], part.convex_planes[4 * f + 2]};
                    EXPECT_GT(part.convex_planes[4 * f + 3], 0) << scene.scene().bodies[b].name << " face " << f;
                    EXPECT_GT(dot(cross(sub(corner(1), corner(0)), sub(corner(2), corner(0))), n), 0)
                        << scene.scene().bodies[b].name << " face " << f;
                }
            }
}

double final_height(const WorldResult& w, size_t body) {
    return w.positions_m[(body * w.frame_count + w.frame_count - 1) * 3 + 2];
}

// A passive hull whose origin is a metre off its surface still holds what lands on it where the
// surface is, and a lathed body rests on its base as Bullet rests it (its points, no margin).
TEST(HullCorpus, HullsWithTheirOriginOffTheSurfaceCollideWhereTheSurfaceIs) {
    Scene s;
    s.world.frame_end = 73;
    // An octagonal slab 10 cm thick whose top face is at z = 0, its object origin 1 m below.
    std::vector<double> slab;
    for (int i = 0; i < 8; ++i)
        for (double z : {0.9, 1.0}) push(slab, 2 * std::cos(kPi * i / 4), 2 * std::sin(kPi * i / 4), z);
    s.bodies.push_back(hull_body("Floor", slab, {0, 0, -1}, BodyType::Passive));
    s.bodies.push_back(hull_body("Bottle", lathed_bottle(16, 40), {0, 0, 0.002}));
    SimulationParameters unperturbed;
    unperturbed.perturb = false;
    const WorldResult w = simulate_world(CompiledScene(s, unperturbed), 1, 0);
    ASSERT_EQ(w.status, WorldStatus::Ok) << w.reject_reason;
    // The bottle's origin is at its base; it stands on the floor's top face at z = 0.
    EXPECT_NEAR(final_height(w, 1), 0.0, 0.003);
}

}  // namespace
}  // namespace mwb
