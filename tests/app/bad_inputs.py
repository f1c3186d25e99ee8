"""Catalogue of bad inputs: each case writes its files into a scratch directory, runs the
mgelastic CLI, and must exit with the expected code and print the expected message (a regular
expression). `bad_inputs.py CLI --list` prints the case ids (one CTest test each),
`bad_inputs.py CLI CASE` runs one case, `bad_inputs.py CLI --markdown` prints the table of
docs/reliability.md with the messages the CLI actually prints."""
import os, re, struct, subprocess, sys, tempfile

BAR = '{"box": {"size": [1, 0.2, 0.2]}}'
FIX = '[{"region": {"box": {"center": [-0.5, 0, 0], "size": [0.1, 1, 1]}}}]'


def scene(extra="", geometry=BAR, constraints=FIX):
    return '{"geometry": %s, "grid": {"resolution": 12}, "constraints": %s%s}' % (
        geometry, constraints, extra)


TRIANGLE_OBJ = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"
CUBE_OFF = ("OFF\n8 12 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
            "3 0 3 2\n3 0 2 1\n3 4 5 6\n3 4 6 7\n3 0 1 5\n3 0 5 4\n3 1 2 6\n3 1 6 5\n"
            "3 2 3 7\n3 2 7 6\n3 3 0 4\n3 3 4 7\n")
NODE = "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n"

# (id, what is wrong, files, arguments, exit code, expected message regex)
CASES = [
    # Scene files
    ("scene_missing", "scene file does not exist", {}, ["run", "nowhere.json"], 2,
     r"nowhere.json: cannot open the scene file"),
    ("scene_json_syntax", "JSON syntax error", {"s.json": '{"geometry": {\n "box": }\n}'},
     ["run", "s.json"], 2, r"s.json:2: invalid JSON"),
    ("scene_unknown_key", "unknown top-level key", {"s.json": scene(', "solve": {}')},
     ["run", "s.json"], 2, r"s.json: /solve: unknown key \(expected one of"),
    ("scene_unknown_nested_key", "unknown nested key",
     {"s.json": '{"geometry": %s, "grid": {"cells": 8}}' % BAR}, ["run", "s.json"], 2,
     r"/grid/cells: unknown key"),
    ("scene_wrong_type", "string where a number belongs",
     {"s.json": '{"geometry": %s, "grid": {"resolution": "64"}}' % BAR}, ["run", "s.json"], 2,
     r"/grid/resolution: expected a number, got string"),
    ("scene_resolution_small", "resolution below 4",
     {"s.json": '{"geometry": %s, "grid": {"resolution": 3}}' % BAR}, ["run", "s.json"], 2,
     r"/grid/resolution: must be >= 4 \(got 3\)"),
    ("scene_not_integer", "fraction where an integer belongs",
     {"s.json": '{"geometry": %s, "grid": {"padding": 1.5}}' % BAR}, ["run", "s.json"], 2,
     r"/grid/padding: expected an integer, got 1.5"),
    ("scene_poisson_half", "Poisson ratio 0.5 (incompressible)",
     {"s.json": scene(', "material": {"poisson_ratio": 0.5}')}, ["run", "s.json"], 2,
     r"/material/poisson_ratio: must be < 0.5 \(got 0.5\)"),
    ("scene_youngs_negative", "negative Young's modulus",
     {"s.json": scene(', "material": {"youngs_modulus": -1}')}, ["run", "s.json"], 2,
     r"/material/youngs_modulus: must be > 0 \(got -1\)"),
    ("scene_density_zero", "zero density",
     {"s.json": scene(', "material": {"density": 0}')}, ["run", "s.json"], 2,
     r"/material/density: must be > 0"),
    ("scene_single_corotated", "single precision with the co-rotated model",
     {"s.json": scene(', "material": {"model": "corotated"}, "solver": {"precision": "single"}')},
     ["run", "s.json"], 2, r"/solver/precision: \"single\" runs the linear model only"),
    ("scene_single_dynamic", "single precision with dynamics",
     {"s.json": scene(', "time": {"quasistatic": false}, "solver": {"precision": "single"}')},
     ["run", "s.json"], 2, r"/solver/precision: \"single\" runs quasistatic scenes only"),
    ("scene_engine_unknown", "unknown engine", {"s.json": scene(', "engine": "fem"')},
     ["run", "s.json"], 2, r"/engine: must be one of grid, tet \(got 'fem'\)"),
    ("scene_geometry_missing", "no geometry", {"s.json": '{"grid": {"resolution": 8}}'},
     ["run", "s.json"], 2, r"/geometry: missing required key"),
    ("shape_two_kinds", "a shape with two kinds",
     {"s.json": scene(geometry='{"box": {"size": [1,1,1]}, "sphere": {"radius": 1}}')},
     ["run", "s.json"], 2, r"/geometry: a shape has exactly one of"),
    ("shape_unknown_kind", "unknown shape kind",
     {"s.json": scene(geometry='{"cone": {"radius": 1}}')}, ["run", "s.json"], 2,
     r"/geometry/cone: unknown shape kind 'cone'"),
    ("shape_negative_radius", "negative sphere radius",
     {"s.json": scene(geometry='{"sphere": {"radius": -1}}')}, ["run", "s.json"], 2,
     r"/geometry/sphere/radius: must be > 0"),
    ("shape_missing_size", "box without size",
     {"s.json": scene(geometry='{"box": {"center": [0, 0, 0]}}')}, ["run", "s.json"], 2,
     r"/geometry/box/size: missing required key"),
    ("shape_difference_one", "difference of a single shape",
     {"s.json": scene(geometry='{"difference": [%s]}' % BAR)}, ["run", "s.json"], 2,
     r"/geometry/difference: expected an array of at least 2 shapes"),
    ("vector_length", "gravity with two components",
     {"s.json": scene(', "loads": {"gravity": [0, -9.81]}')}, ["run", "s.json"], 2,
     r"/loads/gravity: expected an array of 3 numbers"),
    ("vector_entry_type", "gravity with a string entry",
     {"s.json": scene(', "loads": {"gravity": [0, "down", 0]}')}, ["run", "s.json"], 2,
     r"/loads/gravity/1: expected a finite number"),
    ("keyframes_not_increasing", "keyframe times not increasing",
     {"s.json": scene(constraints='[{"region": %s, "motion": "keyframed", "keyframes": '
                      '[{"time": 1}, {"time": 1}]}]' % BAR)}, ["run", "s.json"], 2,
     r"/constraints/0/keyframes/1/time: keyframe times must increase strictly"),
    ("keyframed_without_keys", "keyframed region without keyframes",
     {"s.json": scene(constraints='[{"region": %s, "motion": "keyframed"}]' % BAR)},
     ["run", "s.json"], 2, r"/constraints/0/keyframes: a keyframed region needs at least one"),
    ("keyframes_on_fixed", "keyframes on a fixed region",
     {"s.json": scene(constraints='[{"region": %s, "keyframes": [{"time": 0}]}]' % BAR)},
     ["run", "s.json"], 2, r"/constraints/0/keyframes: keyframes need"),
    ("keyframe_zero_axis", "rotation about a zero axis",
     {"s.json": scene(constraints='[{"region": %s, "motion": "keyframed", "keyframes": '
                      '[{"time": 0, "rotate_axis": [0, 0, 0], "rotate_degrees": 30}]}]' % BAR)},
     ["run", "s.json"], 2, r"/constraints/0/keyframes/0: rotation axis must not be zero"),
    ("solver_tolerance", "tolerance not below 1",
     {"s.json": scene(', "solver": {"tolerance": 1}')}, ["run", "s.json"], 2,
     r"/solver/tolerance: must be < 1"),
    ("solver_cycles_zero", "zero cycles",
     {"s.json": scene(', "solver": {"max_vcycles": 0}')}, ["run", "s.json"], 2,
     r"/solver/max_vcycles: must be >= 1"),
    ("time_dt_zero", "zero time step", {"s.json": scene(', "time": {"dt": 0}')},
     ["run", "s.json"], 2, r"/time/dt: must be > 0"),
    ("time_frames_zero", "zero frames", {"s.json": scene(', "time": {"frames": 0}')},
     ["run", "s.json"], 2, r"/time/frames: must be >= 1"),
    ("output_format", "unknown output format",
     {"s.json": scene(', "output": {"formats": ["stl"]}')}, ["run", "s.json"], 2,
     r"/output/formats/0: must be one of vtk, obj, ply \(got 'stl'\)"),
    # Set-ups that cannot be solved
    ("region_selects_nothing", "constraint region misses the body",
     {"s.json": scene(constraints='[{"region": {"sphere": {"center": [9, 9, 9], '
                      '"radius": 0.1}}}]')}, ["run", "s.json"], 2,
     r"/constraints/0/region: the region selects no cell of the body"),
    ("traction_selects_nothing", "traction region misses the surface",
     {"s.json": scene(', "loads": {"tractions": [{"region": {"sphere": {"center": [9, 9, 9], '
                      '"radius": 0.1}}, "traction": [1, 0, 0]}]}')}, ["run", "s.json"], 2,
     r"/loads/tractions/0/region: the region contains no part of the body's surface"),
    ("body_not_held", "no constraint: singular statics",
     {"s.json": scene(constraints="[]")}, ["run", "s.json"], 2,
     r"s.json: constraints: .*touch no Dirichlet cell; a traction-only body is singular"),
    ("grid_material_regions", "per-region materials on the grid engine",
     {"s.json": scene(', "material": {"regions": [{"region": %s}]}' % BAR)},
     ["run", "s.json"], 2, r"/material/regions: per-region materials are supported by the tet"),
    ("grid_newmark", "Newmark integrator asked of the grid engine (backward Euler only)",
     {"s.json": scene(', "time": {"quasistatic": false, "integrator": "newmark"}')},
     ["run", "s.json"], 2,
     r"/time/integrator: the grid engine integrates with implicit_euler"),
    ("tet_traction_nothing", "tet traction region holds no boundary face",
     {"s.json": scene(', "engine": "tet", "loads": {"tractions": [{"region": {"sphere": '
                      '{"radius": 0.01}}, "traction": [1, 0, 0]}]}')}, ["run", "s.json"], 2,
     r"/loads/tractions/0/region: the region contains no boundary face"),
    ("tet_material_nothing", "tet material region holds no tetrahedron",
     {"s.json": scene(', "engine": "tet", "material": {"regions": [{"region": {"sphere": '
                      '{"center": [9, 9, 9], "radius": 0.1}}}]}')}, ["run", "s.json"], 2,
     r"/material/regions/0/region: the region contains no tetrahedron"),
    # Geometry files in scenes
    ("mesh_missing", "mesh file does not exist",
     {"s.json": scene(geometry='{"mesh": "nowhere.obj"}')}, ["run", "s.json"], 2,
     r"s.json: /geometry/mesh: .*nowhere.obj"),
    ("mesh_open", "a lone triangle bounds no solid",
     {"s.json": scene(geometry='{"mesh": "tri.obj"}'), "tri.obj": TRIANGLE_OBJ},
     ["run", "s.json"], 2, r"/geometry/mesh: .*tri.obj.*(no volume|undefined)"),
    ("tet_mesh_bad_index", "tet engine: .ele index out of range",
     {"s.json": scene(', "engine": "tet"', geometry='{"mesh": "m.node"}'), "m.node": NODE,
      "m.ele": "1 4 0\n1 1 2 3 9\n"}, ["run", "s.json"], 2,
     r"/geometry/mesh: .*m.ele:2: .*9"),
    # Mesh readers (through `mgelastic info`)
    ("obj_bad_number", "OBJ coordinate is not a number",
     {"m.obj": "v 0 0 0\nv 1 0 0\nv 0 1.5.2 0\nf 1 2 3\n"}, ["info", "m.obj"], 2, r"m.obj:3"),
    ("obj_index_range", "OBJ face index out of range",
     {"m.obj": "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n"}, ["info", "m.obj"], 2, r"m.obj:4"),
    ("off_counts", "OFF declares more vertices than present",
     {"m.off": "OFF\n5 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"}, ["info", "m.off"], 2, r"m.off"),
    ("off_not_off", "OFF header missing", {"m.off": "8 12 0\n" + CUBE_OFF[4:]},
     ["info", "m.off"], 2, r"m.off:1"),
    ("stl_truncated", "binary STL shorter than its triangle count",
     {"m.stl": b"\0" * 80 + struct.pack("<I", 3) + b"\0" * 60}, ["info", "m.stl"], 2, r"m.stl"),
    ("ply_bad_header", "PLY without a vertex element",
     {"m.ply": "ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int vertex_indices\n"
               "end_header\n3 0 1 2\n"}, ["info", "m.ply"], 2, r"m.ply"),
    ("mesh_extension", "unsupported mesh extension", {"m.xyz": "0 0 0\n"}, ["info", "m.xyz"], 2,
     r"m.xyz"),
    ("gmsh_truncated", "Gmsh file ends inside $Nodes",
     {"m.msh": "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 4 1 4\n3 1 0 4\n1\n"},
     ["info", "m.msh"], 2, r"m.msh"),
    ("medit_bad_vertex", "MEDIT tetrahedron names vertex 7 of 4",
     {"m.mesh": "MeshVersionFormatted 1\nDimension 3\nVertices\n4\n0 0 0 0\n1 0 0 0\n"
                "0 1 0 0\n0 0 1 0\nTetrahedra\n1\n1 2 3 7 0\nEnd\n"}, ["info", "m.mesh"], 2,
     r"m.mesh:\d+.*7"),
    ("tetgen_missing_ele", "TetGen .node without its .ele", {"m.node": NODE},
     ["info", "m.node"], 2, r"m.ele"),
    ("tet_zero_volume", "flat tetrahedron",
     {"m.node": "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 1 1 0\n", "m.ele": "1 4 0\n1 1 2 3 4\n"},
     ["info", "m.node"], 2, r"m.ele.*(zero|degenerate|volume)"),
    # Command-line flags
    ("flag_poisson", "bench with Poisson ratio 0.5", {}, ["bench", "convergence", "--poisson",
                                                         "0.5"], 2, r"poisson_ratio"),
    ("flag_box_small", "bench box below 4 cells", {}, ["bench", "convergence", "--n", "3"], 2,
     r"--n: must be at least 4"),
    ("flag_threads", "negative thread count", {"s.json": scene()},
     ["run", "s.json", "--threads", "-1"], 2, r"--threads: must be >= 0"),
    ("flag_unknown_bc", "unknown boundary condition", {}, ["bench", "cg", "--bc", "free"], 2,
     r"--bc: must be .mixed. or .dirichlet."),
]


def run_case(cli, case, directory):
    name, _, files, args, code, pattern = case
    for path, content in files.items():
        mode = "wb" if isinstance(content, bytes) else "w"
        with open(os.path.join(directory, path), mode) as f:
            f.write(content)
    result = subprocess.run([cli] + args + (["--output", "out"] if args[0] == "run" else []),
                            cwd=directory, capture_output=True, text=True, timeout=120)
    message = [line for line in result.stderr.splitlines() if line.startswith("error:")]
    return result.returncode, (message[0] if message else result.stderr.strip()), pattern, code


def main():
    cli, what = os.path.abspath(sys.argv[1]), sys.argv[2]
    if what == "--list":
        print(";".join(c[0] for c in CASES))
        return
    if what == "--markdown":
        print("| # | case | input | exit | message |\n|---|---|---|---|---|")
        for i, case in enumerate(CASES, 1):
            with tempfile.TemporaryDirectory() as d:
                rc, message, _, _ = run_case(cli, case, d)
            args = " ".join(case[3])
            print(f"| {i} | `{case[0]}` | {case[1]} (`mgelastic {args}`) | {rc} | "
                  f"`{message.replace('|', '/')}` |")
        return
    case = next(c for c in CASES if c[0] == what)
    with tempfile.TemporaryDirectory() as d:
        rc, message, pattern, code = run_case(cli, case, d)
    print(message)
    assert rc == code, f"exit code {rc}, expected {code}"
    assert re.search(pattern, message), f"message does not match /{pattern}/"


if __name__ == "__main__":
    main()
