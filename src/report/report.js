/*
 * report.js: the HTML report's outline plot (report_html.c): the layer outlines decoded
 * from the page's JSON data block (report_data.c's encoding) and the selected layer's
 * drawn as SVG with the build plans over it. The 3D view is report_view.js's. Plain
 * ES5, no external anything. Sets body's data-rendered when done.
 * Compiled into the binary by the Makefile (report_assets.h), this opening comment left
 * out, every line as it is.
 */
(function(){'use strict';
var data=JSON.parse(document.getElementById('report-data').textContent);
/* the outlines, decoded (report_data.c says how they are encoded) */
function outlines(o){var out=[],n=o.n,q=o.q,t=atob(o.enc),pos=0,run=0;
 function vint(){var v=0,m=1,c;do{c=t.charCodeAt(pos++);v+=(c&127)*m;m*=128;}while(c&128&&pos<t.length);return v;}
 function unzig(u){return u%2?-(u+1)/2:u/2;}
 var below=null;
 for(var l=0;l<o.z.length;l++){var rest=new Array(n),lay={z:o.z[l],r:[],d:[]};
  for(var kind=0;kind<2;kind++){var last=null,a=kind?lay.d:lay.r;
   for(var k=0;k<n;k++){var ref=kind?rest[k]:(below?below[k]:null),p=ref||last||[0,0],pt;
    if(run>0){run--;pt=[p[0],p[1]];}
    else{var tk=vint();if(tk===0)pt=null;else if(tk===1){run=vint();pt=[p[0],p[1]];}else{var dx=unzig(tk-2),dy=unzig(vint());pt=[p[0]+dx,p[1]+dy];}}
    if(pt)last=pt;if(!kind)rest[k]=pt;
    a.push(pt?pt[0]*q:null,pt?pt[1]*q:null);}}
  below=rest;out.push(lay);}
 return out;}
var sel=document.getElementById('layer-select'),plot=document.getElementById('layer-plot');
var zb=document.getElementById('plot-zoom');
var L=outlines(data.layers),ex=[Infinity,Infinity,-Infinity,-Infinity];
function grow(a){for(var i=0;i+1<a.length;i+=2){if(a[i]===null||a[i+1]===null)continue;if(a[i]<ex[0])ex[0]=a[i];if(a[i+1]<ex[1])ex[1]=a[i+1];if(a[i]>ex[2])ex[2]=a[i];if(a[i+1]>ex[3])ex[3]=a[i+1];}}
L.forEach(function(l){grow(l.d);grow(l.r);});
var PL=data.plans||[];
PL.forEach(function(p){p.layers.forEach(function(q){q.g.forEach(grow);});});
function planLayers(i){var out=[];PL.forEach(function(p){p.layers.forEach(function(q,k){if(i>=q.rf&&i<=q.rl)out.push({p:p,q:q,k:k});});});return out;}
function area(c,S,cls){var d='';c.forEach(function(a){if(a.length<6)return;d+='M';for(var j=0;j+1<a.length;j+=2)d+=(j?' L':'')+fmt(S.x(a[j]))+' '+fmt(S.y(a[j+1]));d+=' Z ';});return d?'<path class="'+cls+'" d="'+d+'"/>':'';}
function path(a,S,cls){var pts=[];for(var j=0;j+1<a.length;j+=2)pts.push(fmt(S.x(a[j]))+','+fmt(S.y(a[j+1])));return pts.length>1?'<polyline class="'+cls+'" points="'+pts.join(' ')+'"/>':'';}
function fmt(x){return (Math.round(x*1000)/1000).toString();}
function lines(a,S,cls){var n=a.length/2,out='',cur=[];
 function flush(){if(cur.length>1)out+='<polyline class="'+cls+'" points="'+cur.join(' ')+'"/>';cur=[];}
 for(var i=0;i<=n&&n>0;i++){var k=i%n,x=a[2*k],y=a[2*k+1];if(x===null||y===null){flush();continue;}cur.push(fmt(S.x(x))+','+fmt(S.y(y)));}
 flush();return out;}
function plotLayer(){if(!plot)return;if(!L.length||!(ex[2]>=ex[0])){plot.innerHTML='<p class="note">no per-layer outlines stored with this run</p>';return;}
 var i=sel?parseInt(sel.value,10):0;if(!(i>=0&&i<L.length))i=0;var l=L[i];
 var pls=planLayers(i),plan='',np=0,E=ex,zoomed=false;
 if(zb&&zb.checked&&pls.length){var z=[Infinity,Infinity,-Infinity,-Infinity];
  pls.forEach(function(e){e.q.g.forEach(function(a){for(var j=0;j+1<a.length;j+=2){if(a[j]<z[0])z[0]=a[j];if(a[j+1]<z[1])z[1]=a[j+1];if(a[j]>z[2])z[2]=a[j];if(a[j+1]>z[3])z[3]=a[j+1];}});});
  if(z[2]>=z[0]){var g=0.15*Math.max(z[2]-z[0],z[3]-z[1])+1;E=[z[0]-g,z[1]-g,z[2]+g,z[3]+g];zoomed=true;}}
 var W=640,H=640,m=30,span=Math.max(E[2]-E[0],E[3]-E[1],1e-9),k=(W-2*m)/span;
 var x0=(E[0]+E[2]-span)/2,y0=(E[1]+E[3]-span)/2;
 var S={x:function(x){return m+(x-x0)*k;},y:function(y){return H-m-(y-y0)*k;}};
 pls.forEach(function(e){plan+=area(e.q.m,S,'mr')+area(e.q.g,S,'gr');});
 pls.forEach(function(e){e.q.paths.forEach(function(t){var s=path(t.p,S,t.k===1?'tp ring':'tp raster');if(s){plan+=s;np++;}});});
 var cap=pls.length?pls.map(function(e){return 'section '+e.p.section+' plan layer '+(e.k+1)+'/'+e.p.layers.length;}).join(', ')+': '+np+' paths':'no build plan in this layer';
 var svg='<svg viewBox="0 0 '+W+' '+H+'" width="'+W+'" height="'+H+'" role="img">'+'<style>.dm{fill:none;stroke:#b3261e;stroke-width:2}.rs{fill:none;stroke:#1f5fbf;stroke-width:1.5;stroke-dasharray:6 4}.mr{fill:#f6b26b;fill-opacity:.45;stroke:none;fill-rule:nonzero}.gr{fill:none;stroke:#8a5a00;stroke-width:1;stroke-dasharray:3 3}.tp{fill:none;stroke-width:1.2}.ring{stroke:#0b7a3e}.raster{stroke:#6a1b9a}</style>'+plan+lines(l.r,S,'rs')+lines(l.d,S,'dm')+'<rect x="0" y="0" width="'+W+'" height="44" fill="#fff" fill-opacity=".85"/>'+'<text x="'+m+'" y="20" font-size="13">layer '+i+', z = '+fmt(l.z)+' mm (aligned frame; '+fmt(span)+' mm across'+(zoomed?', zoomed to the build plan':'')+')</text>'+'<text x="'+m+'" y="38" font-size="12" class="plan-caption">'+cap+'</text>'+'</svg>';
 plot.innerHTML=svg;plot.setAttribute('data-paths',String(np));}
if(sel)sel.addEventListener('change',plotLayer);if(zb)zb.addEventListener('change',plotLayer);plotLayer();
document.body.setAttribute('data-rendered','1');
})();
