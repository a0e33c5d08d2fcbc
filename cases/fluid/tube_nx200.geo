// Shock tube with 200 columns (see tube.geo).
Nx = 200;
Include "tube.geo";
