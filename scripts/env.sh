# Environment for headless runs: matplotlib without a display, pyvista through EGL.
export MPLBACKEND="${MPLBACKEND:-Agg}"
export PYVISTA_OFF_SCREEN="${PYVISTA_OFF_SCREEN:-true}"
export VTK_DEFAULT_OPENGL_WINDOW="${VTK_DEFAULT_OPENGL_WINDOW:-vtkEGLRenderWindow}"
