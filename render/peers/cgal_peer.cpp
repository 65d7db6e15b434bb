// cgal_peer.cpp: the CGAL peer of `pp5 bench mesh --peers`.
//   cgal_peer simplify IN.off TARGET_FACES REPS OUT.off
//       Garland-Heckbert plane quadrics (GarlandHeckbert_plane_policies) with
//       CGAL's edge_collapse, placement wrapped in Bounded_normal_change_placement
//       (refuses collapses that flip a face, as pp5's simplifiers do); stops
//       at TARGET_FACES faces.  Prints cgal_faces, cgal_cpu_ms MIN MEDIAN,
//       cgal_wall_ms MIN MEDIAN.
//   cgal_peer hausdorff A.off B.off BOUND_REL
//       bounded_error_symmetric_Hausdorff_distance (one thread) with the error
//       bound BOUND_REL x the bounding-box diagonal of A.  Prints
//       cgal_hausdorff DISTANCE DIAGONAL and cgal_hausdorff_ms.
// Built and run only by render/peers/mesh_peers.sh (never by `make`).
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/bbox.h>
#include <CGAL/Polygon_mesh_processing/distance.h>
#include <CGAL/Polygon_mesh_processing/IO/polygon_mesh_io.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_simplification/edge_collapse.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Bounded_normal_change_placement.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/GarlandHeckbert_policies.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>
#include <vector>

typedef CGAL::Exact_predicates_inexact_constructions_kernel Kernel;
typedef CGAL::Surface_mesh<Kernel::Point_3> Mesh;
namespace SMS = CGAL::Surface_mesh_simplification;
namespace PMP = CGAL::Polygon_mesh_processing;

static double clock_ms(clockid_t id)
{
    timespec t;
    clock_gettime(id, &t);
    return double(t.tv_sec) * 1e3 + double(t.tv_nsec) / 1e6;
}

// Stops once the mesh has at most `target` faces (CGAL's own predicates count edges).
struct Face_count_stop {
    const Mesh *mesh;
    std::size_t target;
    template <typename F, typename Profile>
    bool operator()(const F &, const Profile &, std::size_t, std::size_t) const
    {
        return mesh->number_of_faces() <= target;
    }
};

// PMP's reader repairs the polygon soup first (a simplifier's output may pinch
// a vertex; the repair splits it, which leaves the surface, and so every
// distance, unchanged).
static bool load(const char *path, Mesh &m)
{
    if (!PMP::IO::read_polygon_mesh(path, m) || !CGAL::is_triangle_mesh(m)) {
        std::fprintf(stderr, "cgal_peer: %s: not a triangle mesh\n", path);
        return false;
    }
    return true;
}

static int simplify(const char *in, std::size_t target, int reps, const char *out)
{
    Mesh input;
    if (!load(in, input))
        return 1;
    typedef SMS::GarlandHeckbert_plane_policies<Mesh, Kernel> Policies;
    std::vector<double> cpu, wall;
    Mesh result;
    for (int r = 0; r < reps; r++) {
        Mesh m = input;   // copied outside the timed region
        double c0 = clock_ms(CLOCK_THREAD_CPUTIME_ID), w0 = clock_ms(CLOCK_MONOTONIC);
        Policies policies(m);
        SMS::Bounded_normal_change_placement<Policies::Get_placement> placement(
            policies.get_placement());
        Face_count_stop stop{&m, target};
        SMS::edge_collapse(m, stop, CGAL::parameters::get_cost(policies.get_cost())
                                        .get_placement(placement));
        cpu.push_back(clock_ms(CLOCK_THREAD_CPUTIME_ID) - c0);
        wall.push_back(clock_ms(CLOCK_MONOTONIC) - w0);
        if (r == reps - 1)
            result = m;
    }
    result.collect_garbage();
    if (!CGAL::IO::write_polygon_mesh(out, result, CGAL::parameters::stream_precision(17))) {
        std::fprintf(stderr, "cgal_peer: cannot write %s\n", out);
        return 1;
    }
    std::sort(cpu.begin(), cpu.end());
    std::sort(wall.begin(), wall.end());
    std::printf("cgal_faces %zu\n", std::size_t(result.number_of_faces()));
    std::printf("cgal_cpu_ms %.3f %.3f\n", cpu[0], cpu[cpu.size() / 2]);
    std::printf("cgal_wall_ms %.3f %.3f\n", wall[0], wall[wall.size() / 2]);
    return 0;
}

static int hausdorff(const char *a_path, const char *b_path, double bound_rel)
{
    Mesh a, b;
    if (!load(a_path, a) || !load(b_path, b))
        return 1;
    CGAL::Bbox_3 box = PMP::bbox(a);
    double dx = box.xmax() - box.xmin(), dy = box.ymax() - box.ymin(),
           dz = box.zmax() - box.zmin();
    double diag = std::sqrt(dx * dx + dy * dy + dz * dz);
    double c0 = clock_ms(CLOCK_THREAD_CPUTIME_ID);
    double h = PMP::bounded_error_symmetric_Hausdorff_distance<CGAL::Sequential_tag>(
        a, b, bound_rel * diag);
    std::printf("cgal_hausdorff %.9g %.9g\n", h, diag);
    std::printf("cgal_hausdorff_ms %.1f\n", clock_ms(CLOCK_THREAD_CPUTIME_ID) - c0);
    return 0;
}

int main(int argc, char **argv)
{
    std::string mode = argc > 1 ? argv[1] : "";
    if (mode == "simplify" && argc == 6) {
        int reps = std::atoi(argv[4]);
        return simplify(argv[2], std::strtoul(argv[3], nullptr, 10),
                        reps < 1 || reps > 100 ? 1 : reps, argv[5]);
    }
    if (mode == "hausdorff" && argc == 5)
        return hausdorff(argv[2], argv[3], std::atof(argv[4]));
    std::fprintf(stderr, "usage: cgal_peer simplify IN.off TARGET_FACES REPS OUT.off\n"
                         "       cgal_peer hausdorff A.off B.off BOUND_REL\n");
    return 2;
}
