"""What the experiments in experiments/ share: MeshLab built-in filter steps, mesh measures
and plots (common), and the headless mesh renderer (render_meshes). Run the experiments with
experiments/run, which puts this package and the test harness it builds on on the path."""
