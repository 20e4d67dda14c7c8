// Session 35: a CPU emulation of first_equal_kernel (prepare_on_device.cu, 561e789) a warp at a
// time, lane by lane, against a brute-force search, on 400 random layouts of runs (built by hand:
// g++ -O2 first-equal-emulation.cpp). A record of the check made before call 5, not a test.
#include <cstdio>
#include <cstdint>
#include <cstring>
#include <vector>
#include <random>
#include <algorithm>
struct D2{double x,y;};
const int kUnorderedRunLimit=64,kLookBackLimit=256;
const unsigned kSomeRepeat=1,kUnorderedRun=2,kTooLongRun=4;
unsigned tagof(D2 v){ double a=v.x==0.0?0.0:v.x,b=v.y==0.0?0.0:v.y; uint64_t x,y; memcpy(&x,&a,8); memcpy(&y,&b,8);
  return (unsigned)x ^ ((unsigned)y*0x9E3779B9u) ^ (unsigned)((x^y)>>32);}
unsigned bits_between(int lo,int hi){ lo=std::max(lo,0); hi=std::min(hi,32); if(hi<=lo) return 0u; unsigned bh= hi==32?~0u:(1u<<hi)-1u; return bh & ~((1u<<lo)-1u);}
int ffs_(unsigned m){ return __builtin_ffs(m);} int clz_(unsigned m){return __builtin_clz(m);}
void kernel(const std::vector<D2>& sorted,const std::vector<uint64_t>& codes,int n,int* first,int* head,unsigned* survey){
  for(int wf=0; wf<n; wf+=32){
    int p[32]; bool valid[32],starts[32]; uint64_t code[32]; int q[32];
    for(int l=0;l<32;l++){p[l]=wf+l; valid[l]=p[l]<n; code[l]=valid[l]?codes[p[l]]:0; starts[l]=!valid[l]||p[l]==0||codes[p[l]-1]!=code[l];}
    if(survey){ bool un=false,tl=false; for(int l=0;l<32;l++){ un|= valid[l]&&p[l]>kUnorderedRunLimit&&codes[p[l]-kUnorderedRunLimit-1]==code[l]; tl|= valid[l]&&p[l]>kLookBackLimit&&codes[p[l]-kLookBackLimit-1]==code[l];}
      unsigned found=(un?kUnorderedRun:0)|(tl?kTooLongRun:0); if(found&kTooLongRun){*survey|=found; continue;} *survey|=found; }
    unsigned sm=0; for(int l=0;l<32;l++) if(starts[l]) sm|=1u<<l;
    for(int l=0;l<32;l++) q[l]=p[l];
    if(sm!=~0u){
      int wb=wf;
      if(!(sm&1u)){ uint64_t fc=code[0]; for(int base=wf;;base-=32){ unsigned other=0; for(int l=0;l<32;l++){int at=base-1-l; if(at<0||codes[at]!=fc) other|=1u<<l;} if(other){wb=base-(ffs_(other)-1); break;} } }
      int last=std::min(wf+31,n-1); int begin[32]; unsigned tag[32]; D2 v[32];
      for(int l=0;l<32;l++){ unsigned ab=sm&(l==31?~0u:(2u<<l)-1u); begin[l]=ab? wf+31-clz_(ab):wb; v[l]=valid[l]?sorted[p[l]]:D2{0,0}; tag[l]=tagof(v[l]); }
      for(int base=wb; base<last; base+=32){
        unsigned tt[32]; for(int l=0;l<32;l++) tt[l]= base+l<last? tagof(sorted[base+l]):0u;
        for(int l=0;l<32;l++){ unsigned agree=0; for(int k=0;k<32;k++) agree|=(tt[k]==tag[l]?1u:0u)<<k;
          for(agree&=bits_between(begin[l]-base,q[l]-base); agree; agree&=agree-1){ int j=base+ffs_(agree)-1; D2 w=sorted[j]; if(w.x==v[l].x&&w.y==v[l].y){q[l]=j;break;} } }
      }
    }
    if(survey){ for(int l=0;l<32;l++) if(q[l]!=p[l]) *survey|=kSomeRepeat; continue; }
    for(int l=0;l<32;l++) if(valid[l]){ first[p[l]]=q[l]; head[p[l]]=q[l]==p[l]; }
  }
}
int main(){
  std::mt19937_64 g(7); int fails=0;
  for(int trial=0; trial<400; trial++){
    int n = 1 + g()%3000; std::vector<uint64_t> codes(n); std::vector<D2> pts(n);
    // runs of random lengths (some long), points drawn from a small pool so some repeat
    int maxrun = (trial%4==0)? 400 : (trial%4==1? 300: 120);
    int i=0; uint64_t c=0; int pool = 1 + g()%(trial%3==0? 5: 1000);
    while(i<n){ int L=1+g()%maxrun; if(g()%3==0) L=1; c+=1+g()%3; for(int k=0;k<L&&i<n;k++,i++){ codes[i]=c; int id= trial%5==0 ? i : (int)(g()%pool); pts[i]=D2{ (double)(c*1000+id), (id%7==0)? -0.0 : (double)id*0.5}; if(id%11==0) pts[i].y=0.0; } }
    // brute force
    std::vector<int> bf(n); unsigned exp_un=0,exp_tl=0,exp_rep=0; int b=0;
    for(int p=0;p<n;p++){ if(p==0||codes[p-1]!=codes[p]) b=p; bf[p]=p; for(int j=b;j<p;j++) if(pts[j].x==pts[p].x&&pts[j].y==pts[p].y){bf[p]=j;break;}
      if(p-b>kUnorderedRunLimit) exp_un=1; if(p-b>kLookBackLimit) exp_tl=1; if(bf[p]!=p) exp_rep=1; }
    static int ntl=0,nrep=0,nun=0; ntl+=exp_tl; nrep+=exp_rep; nun+=exp_un; if(trial==399) printf("too long %d repeats %d unordered %d\n",ntl,nrep,nun);
    unsigned survey=0; kernel(pts,codes,n,nullptr,nullptr,&survey);
    bool ok = ((survey&kUnorderedRun)!=0)==(exp_un||exp_tl) && ((survey&kTooLongRun)!=0)==(exp_tl!=0) && (exp_tl || ((survey&kSomeRepeat)!=0)==(exp_rep!=0));
    if(!ok){ printf("trial %d survey %u expected un %u tl %u rep %u\n",trial,survey,exp_un,exp_tl,exp_rep); fails++; }
    if(!exp_tl){ std::vector<int> first(n,-1),head(n,-1); kernel(pts,codes,n,first.data(),head.data(),nullptr);
      for(int p=0;p<n;p++) if(first[p]!=bf[p]||head[p]!=(bf[p]==p)){ printf("trial %d p %d first %d expected %d\n",trial,p,first[p],bf[p]); fails++; break; } }
  }
  printf("fails %d\n",fails); return fails!=0;
}
