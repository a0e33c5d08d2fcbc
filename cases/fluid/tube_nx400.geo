// Shock tube with 400 columns (see tube.geo).
Nx = 400;
Include "tube.geo";
