// The translation unit a library's precompiled header is built with (cmake/FieldlidarPch.cmake):
// no code of its own.
