// Shock tube with 50 columns (see tube.geo).
Nx = 50;
Include "tube.geo";
