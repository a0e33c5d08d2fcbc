// The object that carries the precompiled header every test executable reuses (tests/CMakeLists.txt).
