"""What the tests share (tests/blender, tests/blender_ui, tests/golden) and the benchmarks (bench/) use:

- helpers: scenes, rendering to float arrays, other Blender processes, the unittest runner;
- accuracy: the examples opened for measurement, REFERENCE and the error figures;
- materials: translucent materials, the lit sphere, baking, SubEdit chessboards;
- stability_cases: the hard cases and the moving-light and deformation runs;
- ui_helpers: Blender with its UI under Xvfb (timer-driven steps, screenshots);
- hfunction: Chandrasekhar's H-function and the exact half-space radiance (plain numpy, no bpy);
- truth: physical truth in Cycles, the medium as a volume, and the half-space check's scenes.
- twin_truth: committed physical truths (the converged Cycles twin of a scene, bench/results/truth/)
  and the error against one with its noise taken out (plain numpy where no bpy is needed).

Found through PYTHONPATH: CTest sets it to tests/ for every test (tests/CMakeLists.txt), and
bench/ scripts put tests/ on sys.path themselves.
"""
