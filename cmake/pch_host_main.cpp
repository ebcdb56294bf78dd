// The executable a test's precompiled header is built with (cmake/FieldlidarPch.cmake): no code of
// its own.
int main() {
  return 0;
}
