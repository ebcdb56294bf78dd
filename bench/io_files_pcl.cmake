# bench_io compares fieldlidar's readers with PCL's own loadPCDFile side by side, so it links
# pcl_io/pcl_common directly (PCL's CMake config is unusable on Debian; src/io found the paths).
if(TARGET bench_io)
  target_include_directories(bench_io SYSTEM PRIVATE ${PCL_INCLUDE_DIR})
  target_link_libraries(bench_io PRIVATE ${PCL_IO_LIBRARY} ${PCL_COMMON_LIBRARY})
endif()
