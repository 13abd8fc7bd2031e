// The pyramid closed form (pyramid_closed_form.diff applied) against the forward map and Newton:
// g++ -std=c++20 -O2 -Isrc -I<build> pyramid_check.cpp
#include "volstream/umesh/shape.h"
#include <random>
#include <cstdio>
#include <algorithm>
using namespace vs;
int main(){
  std::mt19937 rng(4242);
  std::uniform_real_distribution<float> around(-0.3f,1.3f), height(-0.3f,0.9f), dist(-0.12f,0.12f), lift(-0.25f,0.25f);
  float wm=0, wn=0; int fails=0, nfail=0;
  for(int trial=0;trial<200000;++trial){
    std::vector<vec3f> x={{0,0,0},{1,0,0},{1,1,0},{0,1,0},{0.5f,0.5f,1}};
    for(auto&p:x) p=p+vec3f(dist(rng),dist(rng),dist(rng));
    x[2].z+=lift(rng); x[3].z+=lift(rng);
    vec3f made{around(rng),around(rng),height(rng)};
    float w[8]; vec3f d[8]; shape::weights(5,made.x,made.y,made.z,w,d);
    vec3f p(0.f); for(int i=0;i<5;++i) p=p+x[i]*w[i];
    auto s=shape::iso_solve(5,x.data()); vec3f c;
    if(!shape::pyramid_params(s.map,p-s.origin,c)){++fails;continue;}
    if(shape::params_outside(5,made.x,made.y,made.z)< -0.01f) wm=std::max({wm,fabsf(c.x-made.x),fabsf(c.y-made.y),fabsf(c.z-made.z)});
    auto nn=s; if(shape::newton_params(5,nn,p-s.origin,nullptr,false,1)&&shape::params_outside(5,nn.params.x,nn.params.y,nn.params.z)<0){auto dd=nn.params-c; wn=std::max({wn,fabsf(dd.x),fabsf(dd.y),fabsf(dd.z)});}
  }
  printf("worst vs map %g vs newton %g fails %d\n",wm,wn,fails);
}
