// Session 35: the lengths of runs of equal 64-bit codes (32 bits a coordinate, as refined_morton)
// in the benchmark's 4096^2 input of a distribution (seed 42). Built by hand against libexpanse.a:
//   g++ -O2 -std=c++20 -Iengine/include kuzmin-run-lengths.cpp build/engine/libexpanse.a -lpthread
#include <expanse/generate.hpp>
#include <cstdio>
#include <cmath>
#include <vector>
#include <algorithm>
#include <cstdint>
int main(int argc,char**argv){
  const size_t n=4096ull*4096; auto p=expanse::generate_points(argv[1],n,42);
  double minx=1e300,maxx=-1e300,miny=1e300,maxy=-1e300;
  for(auto&q:p){minx=std::min(minx,q.x);maxx=std::max(maxx,q.x);miny=std::min(miny,q.y);maxy=std::max(maxy,q.y);}
  double w=std::max(maxx-minx,maxy-miny); double s=std::ldexp(1.0,32)/w;
  std::vector<std::uint64_t> k(n);
  for(size_t i=0;i<n;i++){ uint64_t a=(uint64_t)((p[i].x-minx)*s), b=(uint64_t)((p[i].y-miny)*s); k[i]=(a<<32)|b; }
  std::sort(k.begin(),k.end());
  size_t lims[]={1,2,8,64,512,4096,1ull<<40}; size_t runs[7]={0},pts[7]={0}; size_t mx=0;
  for(size_t i=0;i<n;){size_t j=i; while(j<n&&k[j]==k[i]) j++; size_t L=j-i; mx=std::max(mx,L); int b=0; while(L>lims[b]) b++; runs[b]++; pts[b]+=L; i=j;}
  printf("box %g max run %zu\n",w,mx);
  for(int b=0;b<7;b++) printf("<=%zu: runs %zu points %zu (%.3f)\n",lims[b],runs[b],pts[b],pts[b]/(double)n);
}
