// Dummy geometry for the case-reader tests: only its existence is checked.
Point(1) = {0, 0, 0, 1};
