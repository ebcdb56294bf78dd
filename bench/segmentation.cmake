# bench_segmentation runs PCL's EuclideanClusterExtraction side by side with ours as the baseline:
# link the PCL libraries directly (PCL's CMake config is broken on Debian, see src/io).
if(TARGET bench_segmentation)
  find_path(BENCH_SEG_PCL_INCLUDE_DIR pcl/segmentation/extract_clusters.h
            PATH_SUFFIXES pcl-1.13 pcl-1.12 REQUIRED)
  find_library(BENCH_SEG_PCL_SEGMENTATION pcl_segmentation REQUIRED)
  find_library(BENCH_SEG_PCL_SEARCH pcl_search REQUIRED)
  find_library(BENCH_SEG_PCL_KDTREE pcl_kdtree REQUIRED)
  find_library(BENCH_SEG_PCL_COMMON pcl_common REQUIRED)
  find_library(BENCH_SEG_FLANN flann_cpp REQUIRED)
  target_include_directories(bench_segmentation SYSTEM PRIVATE ${BENCH_SEG_PCL_INCLUDE_DIR})
  target_link_libraries(bench_segmentation PRIVATE ${BENCH_SEG_PCL_SEGMENTATION}
    ${BENCH_SEG_PCL_SEARCH} ${BENCH_SEG_PCL_KDTREE} ${BENCH_SEG_PCL_COMMON} ${BENCH_SEG_FLANN})
  target_compile_definitions(bench_segmentation PRIVATE FIELDLIDAR_BENCH_WITH_PCL=1)
endif()
