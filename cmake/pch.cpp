// The source of gport_pch, the target that builds the shared precompiled header
// (cmake/GportPch.cmake).
