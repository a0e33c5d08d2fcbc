// Shock tube with 100 columns (see tube.geo).
Nx = 100;
Include "tube.geo";
