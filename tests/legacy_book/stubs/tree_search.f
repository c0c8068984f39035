c     Not the book's: tree_search.f is not in the stored index.  A stub so
c     that single_step links; param.inc selects nnps = 1 (direct_find).
      subroutine tree_search(itimestep, ntotal,hsml,x,niac,pair_i,
     &           pair_j,w,dwdx,countiac)
      implicit none
      include 'param.inc'
      integer itimestep, ntotal, niac, pair_i(max_interaction),
     &        pair_j(max_interaction), countiac(maxn)
      double precision hsml(maxn), x(dim,maxn), w(max_interaction),
     &       dwdx(dim,max_interaction)
      print *,' tree_search: not available in this copy'
      stop
      end
